// runStudy: the plan checked and the scene loaded (plan.cpp), the reference found or rendered
// (reference.cpp), each variant rendered at each spp `repeats` times and measured (measure.cpp), then the
// summary, conclusion (summary.cpp), plots and report (report.cpp). Every process of a shared study runs
// it in step; only the writing process holds a StudyWriter, the one object that measures into files.
#include "study/report_html.h"
#include "study/study_parts.h"

#include "accel/accel.h"
#include "io/files.h"
#include "io/input_error.h"
#include "render/checkpoint.h"
#include "render/long_render.h"
#include "render/progress.h"
#include "scene/scene.h"
#include "study/config.h"

#include <fmt/format.h>

#include <algorithm>
#include <map>
#include <mutex>
#include <optional>

namespace fs = std::filesystem;

namespace symphong {

std::function<void(std::size_t)>& rowObserver() {
    static std::function<void(std::size_t)> observer;
    return observer;
}

void setStudyRowObserver(std::function<void(std::size_t rows)> observer) { rowObserver() = std::move(observer); }

RenderResult StudyRuntime::render(const Scene& scene, const Accel& accel, const Estimator& estimator, const RenderSettings& settings,
                                  std::atomic<std::uint64_t>* progress) const {
    return symphong::render(scene, accel, estimator, settings, progress);
}

StopReason StudyRuntime::renderPasses(const Scene& scene, const Accel& accel, const Estimator& estimator, const RenderSettings& settings,
                                      const StopRules& rules, RenderState& state, const std::function<void(const PassReport&)>& afterPass,
                                      std::atomic<std::uint64_t>* progress) const {
    return renderProgressive(scene, accel, estimator, settings, rules, state, afterPass, progress);
}

namespace {

/// What only the writing process holds: the output directory and every file the study writes.
class StudyWriter {
public:
    StudyWriter(const StudyConfig& c, const std::string& sceneName, std::uint32_t heatSpp, const std::vector<StudyVariant>& variants,
                int processes)
        : c_(c), dir_(c.outDir), sceneName_(sceneName), heatSpp_(heatSpp), variants_(variants), processes_(processes) {}

    /// The output directories and an empty results.csv (fails early when they cannot be written).
    void prepare() const {
        std::error_code ec;
        fs::create_directories(dir_ / "renders", ec);
        fs::create_directories(dir_ / "heatmaps", ec);
        if (ec || !fs::is_directory(dir_)) throw InputError(fmt::format("--out {}: cannot create the directory", c_.outDir));
        writeFile((dir_ / "results.csv").string(), std::string(kStudyCsvHeader) + "\n");
    }
    const fs::path& dir() const { return dir_; }

    /// A variant's first repeat at each spp, for report.html (half floats: what the page shows).
    void writeSppRender(const std::string& label, std::uint32_t spp, const Image& image) const {
        writeExr(image, sppRenderPath(dir_, label, spp).string(), true);
    }

    /// A variant's render at the heat maps' spp: its PNG and its relative error map.
    void writeRender(const std::string& label, const Image& image, const Reference& ref) const {
        writePng(image, (dir_ / "renders" / (label + ".png")).string());
        const std::vector<float> map = relativeErrorMap(image, ref.image);
        writeFile((dir_ / "heatmaps" / (label + ".f32")).string(),
                  std::string(reinterpret_cast<const char*>(map.data()), map.size() * sizeof(float)));
    }

    /// results.csv and results.json with the rows so far, their summary and conclusion.
    void writeResults(StudyOutcome& outcome, const Reference& ref) const {
        writeFile((dir_ / "results.csv").string(), studyCsv(outcome.rows));
        nlohmann::json variantList = nlohmann::json::array();
        for (const auto& v : variants_)
            variantList.push_back({{"label", v.label},
                                   {"estimator", v.estimator},
                                   {"sampler", v.sampler},
                                   {"mode", symmetricModeName(v.mode)},
                                   {"split", v.split}});
        const Crop crop = this->crop();
        nlohmann::json j;
        j["config"] = {
            {"scene", sceneName_},
            {"scene_spec", c_.scene},
            {"estimators", c_.estimators},
            {"samplers", c_.samplers},
            {"variants", variantList},
            {"spp", c_.spps},
            {"symmetric_orbit", c_.options.symmetricOrbit},
            {"budget_pairs", c_.budgetPairs},
            {"joint_first_bounce", c_.jointFirstBounce},
            {"repeats", c_.repeats},
            {"width", c_.width},
            {"height", c_.height},
            {"max_depth", c_.maxDepth},
            {"seed", c_.seed},
            {"processes", processes_},
            {"reference",
             {{"path", c_.referencePath},
              {"estimator", c_.referenceEstimator},
              {"spp", c_.referenceSpp},
              {"mean_luminance", ref.mean.mean},
              {"pixel_variance", ref.noise}}},
            {"heatmap", {{"spp", heatSpp_}, {"width", c_.width}, {"height", c_.height}, {"crop", {crop.x, crop.y, crop.w, crop.h}}}}};
        j["settings"] = studySettingsJson(c_);
        j["rows"] = nlohmann::json::array();
        for (const auto& r : outcome.rows) j["rows"].push_back(rowJson(r));
        outcome.summary = summarizeStudy(outcome.rows);
        j["summary"] = nlohmann::json::array();
        for (const auto& s : outcome.summary) j["summary"].push_back(summaryJson(s));
        outcome.conclusion = studyConclusion(outcome.summary, c_.spps);
        j["conclusion"] = outcome.conclusion;
        writeFile((dir_ / "results.json").string(), j.dump(1) + "\n");
    }

    /// The last results, the plots and report.md.
    void finish(StudyOutcome& outcome, const Reference& ref) const {
        writeResults(outcome, ref);
        if (!outcome.cancelled && c_.plots) outcome.plotted = makePlots(c_, dir_);
        // The answer's and tables' bootstrap intervals, once for report.md, report.html and the command line;
        // none for an interrupted study (thousands of resamplings per cell take seconds under a sanitizer,
        // more than a job stopped by its launcher has).
        const int draws = outcome.cancelled ? 0 : kReportDraws;
        outcome.answer = studyAnswer(c_, outcome.rows, outcome.summary, draws);
        const std::vector<ReportTable> tables = studyTables(c_, outcome.rows, outcome.summary, draws);
        const ReportInputs in{c_,        sceneName_,        outcome.summary, outcome.rows,   outcome.conclusion, ref, outcome.plotted,
                              heatSpp_, outcome.cancelled, processes_,      outcome.answer, tables};
        writeFile((dir_ / "report.md").string(), reportMarkdown(in));
        writeFile((dir_ / "details.md").string(), reportDetailsMarkdown(in));
        // Not when interrupted: its FLIP maps take seconds that a job stopped by its launcher does not have
        // (mpirun kills the ranks a second after SIGTERM); the resumed study writes it.
        std::error_code ec;
        if (outcome.cancelled)
            fs::remove(dir_ / "report.html", ec);  // an earlier run's page would not match these rows
        else
            writeFile((dir_ / "report.html").string(), reportHtml(reportHtmlData(in, dir_)));
    }

private:
    Crop crop() const { return {c_.width / 3, c_.height / 3, std::max(1, c_.width / 3), std::max(1, c_.height / 3)}; }

    const StudyConfig& c_;
    fs::path dir_;
    std::string sceneName_;
    std::uint32_t heatSpp_;
    const std::vector<StudyVariant>& variants_;
    int processes_;
};

/// The study's progress bar: the work done before the render in flight (in estimated seconds), the
/// camera samples of that render so far times its cost per sample, and its label.
struct StudyProgress {
    std::atomic<std::uint64_t> samples{0};
    double doneBefore = 0, currentCost = 0;
    std::string label = "reference";
    std::mutex labelMutex;

    void start(std::string text, double cost) {
        {
            std::lock_guard<std::mutex> lock(labelMutex);
            label = std::move(text);
        }
        currentCost = cost;
        samples = 0;
    }
    void finished(double work) {
        doneBefore += work;
        samples = 0;
    }
    ProgressBar bar(double total, bool show) {
        return ProgressBar([this] { return doneBefore + currentCost * static_cast<double>(samples.load(std::memory_order_relaxed)); },
                           total,
                           [this] {
                               std::lock_guard<std::mutex> lock(labelMutex);
                               return label;
                           },
                           show);
    }
};

/// One study in progress, in one process.
class StudyRun {
public:
    StudyRun(const StudyConfig& config, const std::atomic<bool>* cancel, const StudyRuntime& rt) : c_(config), cancel_(cancel), rt_(rt) {}

    StudyOutcome run(bool showProgress);

private:
    void prepare();
    RenderSettings base() const;
    double pilotCost(const std::string& name, const EstimatorOptions& options, const std::string& sampler) const;
    double plannedWork();
    bool renderReference();
    /// The repeats of one variant at one spp (and its variance budget at the top spp); false when cancelled.
    bool runGroup(std::uint32_t spp, std::size_t ei);
    double budgetVariance(std::uint32_t spp, std::size_t ei, const Estimator& est);

    StudyConfig c_;
    const std::atomic<bool>* cancel_;
    const StudyRuntime& rt_;
    std::uint32_t heatSpp_ = 0;
    std::vector<StudyVariant> variants_;
    Scene scene_;
    std::unique_ptr<Accel> accel_;
    nlohmann::json refKey_;
    Reference ref_;
    RenderIdentity refIdentity_;         ///< what the reference's checkpoint must match
    RenderState refState_;               ///< the reference so far (from its checkpoint when resuming)
    KeptGroups kept_;                    ///< --resume: the finished groups of rows of the earlier run
    std::optional<StudyWriter> writer_;  ///< only in the writing process
    std::map<std::string, double> cost_;
    StudyProgress progress_;
    int rowIndex_ = 0, rowCount_ = 0;
    StudyOutcome outcome_;
};

// Every process checks the configuration and loads the scene; the writer also makes the output
// directory and looks for a reference. Bad input in any process stops all of them with one message
// (the process that met it keeps its exception's type).
void StudyRun::prepare() {
    std::exception_ptr failure;
    std::string error;
    try {
        heatSpp_ = checkConfig(c_);
        variants_ = studyVariants(c_);
        scene_ = loadScene(c_.scene);
        refKey_ = referenceKey(c_);
        if (rt_.writer()) {
            for (const std::string& w : scene_.warnings) fmt::print(stderr, "symphong: warning: {}\n", w);
            if (c_.resume)
                kept_ = keptGroups(c_, fs::path(c_.outDir), [](const std::string& m) { fmt::print(stderr, "symphong: {}\n", m); });
            writer_.emplace(c_, scene_.name, heatSpp_, variants_, rt_.processes());
            writer_->prepare();
            ref_ = existingReference(c_, writer_->dir(), refKey_);
            refIdentity_ = {c_.scene, sceneFingerprint(scene_, c_.scene), refKey_};
            refState_ = RenderState(c_.width, c_.height, c_.referenceSpp);
            if (!ref_.have && c_.resume) resumeReference(writer_->dir() / "reference.ckpt", refIdentity_, refState_);
        }
    } catch (const InputError& e) {
        failure = std::current_exception();
        error = e.what();
    }
    if (const std::string agreed = rt_.agreeOnError(error); !agreed.empty()) {
        if (failure && agreed == error) std::rethrow_exception(failure);
        throw InputError(agreed);
    }
    ref_.have = rt_.writersValue(ref_.have);
    accel_ = std::make_unique<Accel>(scene_);
}

RenderSettings StudyRun::base() const {
    RenderSettings base;
    base.width = c_.width;
    base.height = c_.height;
    base.threads = c_.threads;
    base.trace.maxDepth = c_.maxDepth;
    base.cancel = cancel_;
    return base;
}

// Cost per camera sample of an estimator, from a small pilot render, so the progress bar's ETA accounts
// for estimators that trace 24 paths per sample.
double StudyRun::pilotCost(const std::string& name, const EstimatorOptions& options, const std::string& sampler) const {
    RenderSettings pilot = base();
    pilot.width = pilot.height = 24;
    pilot.spp = 2;
    pilot.seed = 99;
    pilot.sampler = sampler;
    pilot.cancel = nullptr;
    const auto est = makeEstimator(name, options);
    const RenderResult r = render(scene_, *accel_, *est, pilot);
    return std::max(1e-9, r.stats.seconds / static_cast<double>(r.stats.samples));
}

// The work of the whole study in estimated seconds; only the writer shows progress, the others skip the pilots.
double StudyRun::plannedWork() {
    double total = 0;
    if (writer_)
        for (const auto& v : variants_) {
            cost_[v.label] = pilotCost(v.estimator, variantOptions(c_, v), v.sampler);
            for (auto s : c_.spps) total += cost_[v.label] * s * c_.width * c_.height * c_.repeats;
        }
    const double refCost = ref_.have || !writer_ ? 0.0 : pilotCost(c_.referenceEstimator, c_.options, c_.referenceSampler);
    progress_.currentCost = refCost;
    return total + refCost * c_.referenceSpp * c_.width * c_.height;
}

// The reference, unless it was given or cached: rendered in passes up to --reference-spp or until
// --reference-error, with a checkpoint in the output directory (resumed with --resume); false when
// cancelled.
bool StudyRun::renderReference() {
    const double refWork = progress_.currentCost * c_.referenceSpp * c_.width * c_.height;
    if (!ref_.have) {
        RenderSettings rs = base();
        rs.spp = c_.referenceSpp;
        rs.seed = mixSeed(c_.seed, 0xFEFE);
        rs.sampler = c_.referenceSampler;
        const auto est = makeEstimator(c_.referenceEstimator, c_.options);
        StopRules rules;
        rules.targetError = c_.referenceError;
        const std::string checkpoint = writer_ ? (writer_->dir() / "reference.ckpt").string() : std::string();
        CheckpointSchedule schedule(kStudyCheckpointInterval, refState_.seconds);
        if (!writer_) refState_ = RenderState(c_.width, c_.height, c_.referenceSpp);
        progress_.samples = refState_.samples;
        const StopReason why = rt_.renderPasses(
            scene_, *accel_, *est, rs, rules, refState_,
            [&](const PassReport& r) {
                if (!schedule.due(r.seconds, r.nextPassSeconds, r.last)) return;
                writeCheckpoint(checkpoint, refIdentity_, refState_);
                schedule.written(r.seconds);
            },
            &progress_.samples);
        if (rt_.writersValue(why == StopReason::Cancelled)) return false;
        outcome_.referenceRendered = true;
        if (writer_) {
            ref_ = referenceFromRender(c_, resultOf(refState_, rs.sampler), refState_.samplesReached());
            writeReferenceCache(ref_, refKey_, refState_.seconds, writer_->dir());
            std::error_code ec;
            fs::remove(checkpoint, ec);  // the cache holds the finished reference
        }
    }
    progress_.finished(refWork);
    if (writer_) writePng(ref_.image, (writer_->dir() / "reference.png").string());
    return true;
}

bool StudyRun::runGroup(std::uint32_t spp, std::size_t ei) {
    const StudyVariant& variant = variants_[ei];
    const std::string& name = variant.label;
    if (rt_.writersValue(kept_.count({spp, name}) > 0)) {  // --resume: this group was finished before
        rowIndex_ += c_.repeats;
        progress_.finished(cost_[name] * spp * c_.width * c_.height * c_.repeats);
        if (!writer_) return true;
        for (const StudyRow& row : kept_.at({spp, name})) outcome_.rows.push_back(row);
        outcome_.keptRows += c_.repeats;
        writer_->writeResults(outcome_, ref_);
        return true;
    }
    const auto est = makeEstimator(variant.estimator, variantOptions(c_, variant));
    std::vector<Image> images;
    std::vector<MeanWithError> means;
    const std::size_t firstRow = outcome_.rows.size();
    for (int rep = 0; rep < c_.repeats; ++rep) {
        progress_.start(fmt::format("{} {} spp, repeat {}/{} (row {}/{})", name, spp, rep + 1, c_.repeats, rowIndex_ + 1, rowCount_),
                        cost_[name]);
        RenderSettings rs = base();
        rs.spp = spp;
        rs.sampler = variant.sampler;
        rs.trace.firstHitSplit = variant.split;
        rs.trace.jointFirstBounce = c_.jointFirstBounce;
        rs.seed = mixSeed(mixSeed(mixSeed(c_.seed, ei + 1), spp), static_cast<std::uint64_t>(rep));
        const RenderResult r = rt_.render(scene_, *accel_, *est, rs, &progress_.samples);
        progress_.finished(cost_[name] * spp * c_.width * c_.height);
        ++rowIndex_;
        if (r.cancelled) {
            outcome_.rows.resize(firstRow);  // keep only whole groups: their group columns are complete
            return false;
        }
        if (!writer_) continue;  // it helped render; the writer measures
        const StudyRow row = measureRow(c_, scene_.name, variant, spp, rep, r, ref_);
        means.push_back({row.meanLuminance, row.meanStdError});
        if (rep == 0) writer_->writeSppRender(name, spp, r.image);
        if (spp == heatSpp_ && rep == 0) writer_->writeRender(name, r.image, ref_);
        images.push_back(r.image);
        outcome_.rows.push_back(row);
        if (rowObserver()) rowObserver()(outcome_.rows.size());
    }
    const double firstBounce = spp == c_.spps.back() && c_.budgetPairs > 0 ? budgetVariance(spp, ei, *est) : -1;
    if (outcome_.cancelled) {
        outcome_.rows.resize(firstRow);
        return false;
    }
    if (!writer_) return true;
    fillGroupColumns(outcome_.rows, firstRow, images, means, ref_, firstBounce);
    writer_->writeResults(outcome_, ref_);
    return true;
}

// The variance budget at the top spp: pairs of renders that differ only in the first bounce's numbers.
double StudyRun::budgetVariance(std::uint32_t spp, std::size_t ei, const Estimator& est) {
    const StudyVariant& variant = variants_[ei];
    double sum = 0;
    for (int b = 0; b < c_.budgetPairs && !outcome_.cancelled; ++b) {
        RenderSettings rs = base();
        rs.spp = spp;
        rs.sampler = variant.sampler;
        rs.trace.firstHitSplit = variant.split;
        rs.trace.jointFirstBounce = c_.jointFirstBounce;
        rs.seed = mixSeed(mixSeed(mixSeed(c_.seed, ei + 1), 0xB0D6E7), static_cast<std::uint64_t>(b));
        Image pair[2];
        for (std::uint32_t stream = 1; stream <= 2 && !outcome_.cancelled; ++stream) {
            progress_.start(fmt::format("{} {} spp, variance budget {}/{}", variant.label, spp, b + 1, c_.budgetPairs),
                            progress_.currentCost);
            rs.trace.firstBounceStream = stream;
            const RenderResult r = rt_.render(scene_, *accel_, est, rs, &progress_.samples);
            progress_.finished(cost_[variant.label] * spp * c_.width * c_.height);
            outcome_.cancelled = r.cancelled;
            pair[stream - 1] = r.image;
        }
        if (!outcome_.cancelled && writer_) sum += halfSquaredDifference(pair[0], pair[1]);
    }
    return sum / c_.budgetPairs;
}

StudyOutcome StudyRun::run(bool showProgress) {
    prepare();
    const double total = plannedWork();
    rowCount_ = static_cast<int>(variants_.size() * c_.spps.size()) * c_.repeats;
    ProgressBar bar = progress_.bar(total, showProgress);
    if (!renderReference()) {
        bar.finish();
        outcome_.cancelled = true;
        return outcome_;
    }
    for (std::uint32_t spp : c_.spps) {
        for (std::size_t ei = 0; ei < variants_.size() && !outcome_.cancelled; ++ei) outcome_.cancelled = !runGroup(spp, ei);
        if (outcome_.cancelled) break;
    }
    bar.finish();
    if (writer_) writer_->finish(outcome_, ref_);
    return outcome_;
}

}  // namespace

StudyOutcome runStudy(const StudyConfig& config, const std::atomic<bool>* cancel, bool showProgress, const StudyRuntime* runtime) {
    const StudyRuntime inThisProcess;
    StudyRun run(config, cancel, runtime ? *runtime : inThisProcess);
    return run.run(showProgress);
}

}  // namespace symphong
