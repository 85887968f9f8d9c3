// runStudy: the plan checked and the scene loaded (plan.cpp), the reference found or rendered
// (reference.cpp), each variant rendered at each spp `repeats` times and measured (measure.cpp); with
// --target-interval, rounds of paired repeats at the top spp until the answer's comparisons are settled
// (study/comparisons.h) or --time or --max-repeats ends them; then the summary, conclusion (summary.cpp),
// plots and report (report.cpp). Every process of a shared study runs it in step; only the writing process
// holds a StudyWriter (writer.cpp), the one object that measures into files.
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
#include <set>
#include <tuple>

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

double secondsSince(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

/// One study in progress, in one process.
class StudyRun {
public:
    StudyRun(const StudyConfig& config, const std::atomic<bool>* cancel, const StudyRuntime& rt) : c_(config), cancel_(cancel), rt_(rt) {}

    StudyOutcome run(bool showProgress);

private:
    void prepare();
    double pilotCost(const RenderSettings& pilot, const std::string& estimator, const EstimatorOptions& options) const;
    double plannedWork();
    bool renderReference();
    /// The repeats of every variant at one spp (and their variance budget at the top spp); false when cancelled.
    bool runSpp(std::uint32_t spp);
    void orderRows();
    bool renderRepeat(std::uint32_t spp, std::size_t ei, int rep, const Estimator& est);
    void refreshGroup(std::uint32_t spp, const std::string& label);
    void repeatUntilSettled();
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
    std::map<std::pair<std::uint32_t, std::string>, GroupImages> groups_;  ///< the writer's, by (spp, variant)
    std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
    bool showProgress_ = false;
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

// CPU time per camera sample of a variant (or the reference), from a small pilot render with its settings,
// so that the progress bar's ETA accounts for estimators that trace 24 paths per sample, first-hit splits
// and EARS (pilotRenderSettings). CPU time, not wall: a render this small keeps the threads only partly busy
// (on sky-n10, the pilots' EARS / phong ratio by wall time swung 1.5-2.9 between runs, by CPU time 3.2,
// where the study's 128x96 renders take 4.3 times phong's time); the bar only needs the costs' proportions.
double StudyRun::pilotCost(const RenderSettings& pilot, const std::string& estimator, const EstimatorOptions& options) const {
    const auto est = makeEstimator(estimator, options);
    const RenderResult r = render(scene_, *accel_, *est, pilot);
    return std::max(1e-9, r.stats.cpuSeconds / static_cast<double>(r.stats.samples));
}

// The work of the whole study in estimated CPU seconds (the bar shows its proportions); only the writer shows
// progress, the others skip the pilots.
double StudyRun::plannedWork() {
    double total = 0;
    if (writer_)
        for (const auto& v : variants_) {
            cost_[v.label] = pilotCost(pilotRenderSettings(c_, v), v.estimator, variantOptions(c_, v));
            for (auto s : c_.spps) total += cost_[v.label] * s * c_.width * c_.height * c_.repeats;
        }
    const double refCost = ref_.have || !writer_ ? 0.0
                                                 : pilotCost(pilotRenderSettings(c_, referenceRenderSettings(c_, c_.referenceSpp)),
                                                             c_.referenceEstimator, c_.options);
    progress_.currentCost = refCost;
    return total + refCost * c_.referenceSpp * c_.width * c_.height;
}

// The reference, unless it was given or cached: rendered in passes up to --reference-spp or until
// --reference-error, with a checkpoint in the output directory (resumed with --resume); false when
// cancelled.
bool StudyRun::renderReference() {
    const double refWork = progress_.currentCost * c_.referenceSpp * c_.width * c_.height;
    if (!ref_.have) {
        RenderSettings rs = referenceRenderSettings(c_, c_.referenceSpp);
        rs.cancel = cancel_;
        rs.seed = mixSeed(c_.seed, 0xFEFE);
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

// The repeats of every variant at one spp, interleaved: repeat r of each variant in turn, then repeat r + 1
// (A B C A B C ...), so that a change of the machine's speed during the study touches every variant alike
// and the paired ratios cancel it; then each group's variance budget (top spp) and group columns.
bool StudyRun::runSpp(std::uint32_t spp) {
    std::vector<std::unique_ptr<Estimator>> estimators(variants_.size());
    for (std::size_t ei = 0; ei < variants_.size(); ++ei) {
        const StudyVariant& v = variants_[ei];
        if (rt_.writersValue(kept_.count({spp, v.label}) > 0)) {  // --resume: this group was finished before
            progress_.finished(cost_[v.label] * spp * c_.width * c_.height * c_.repeats);
            rowIndex_ += c_.repeats;
            if (!writer_) continue;
            for (const StudyRow& row : kept_.at({spp, v.label})) outcome_.rows.push_back(row);
            outcome_.keptRows += static_cast<int>(kept_.at({spp, v.label}).size());
            continue;
        }
        estimators[ei] = makeEstimator(v.estimator, variantOptions(c_, v));
    }
    for (int rep = 0; rep < c_.repeats && !outcome_.cancelled; ++rep) {
        for (std::size_t ei = 0; ei < variants_.size() && !outcome_.cancelled; ++ei) {
            if (!estimators[ei]) continue;
            const std::string& name = variants_[ei].label;
            progress_.start(fmt::format("{} {} spp, repeat {}/{} (row {}/{})", name, spp, rep + 1, c_.repeats, rowIndex_ + 1, rowCount_),
                            cost_[name]);
            outcome_.cancelled = !renderRepeat(spp, ei, rep, *estimators[ei]);
            ++rowIndex_;
        }
        // Not after the last round: its groups are whole but their group columns are filled below, and a
        // resume keeps whole groups as they are on disk (a kill in between left zeros there).
        if (writer_ && !outcome_.cancelled && rep + 1 < c_.repeats) writer_->writeResults(outcome_, ref_);
    }
    for (std::size_t ei = 0; ei < variants_.size() && !outcome_.cancelled; ++ei) {
        if (!estimators[ei]) continue;
        const double firstBounce = spp == c_.spps.back() && c_.budgetPairs > 0 ? budgetVariance(spp, ei, *estimators[ei]) : -1;
        if (writer_ && !outcome_.cancelled) groups_[{spp, variants_[ei].label}].firstBounce = firstBounce;
    }
    if (outcome_.cancelled) {
        // Keep only whole groups (their group columns are complete): those of this spp with every repeat.
        std::set<std::string> partial;
        for (const StudyVariant& v : variants_)
            if (repeatsOf(outcome_.rows, v.label, spp) < c_.repeats) partial.insert(v.label);
        std::erase_if(outcome_.rows, [&](const StudyRow& r) { return r.spp == spp && partial.count(r.variant); });
        for (std::size_t ei = 0; ei < variants_.size(); ++ei)
            if (writer_ && estimators[ei] && !partial.count(variants_[ei].label)) refreshGroup(spp, variants_[ei].label);
        orderRows();
        return false;
    }
    if (!writer_) return true;
    for (std::size_t ei = 0; ei < variants_.size(); ++ei)
        if (estimators[ei]) refreshGroup(spp, variants_[ei].label);
    orderRows();
    writer_->writeResults(outcome_, ref_);
    return true;
}

// The rows in the order of the tables: by spp, variant (the study's order), then repeat, however they were
// rendered (interleaved, in rounds, or kept from an earlier run).
void StudyRun::orderRows() {
    std::map<std::string, std::size_t> variantIndex;
    for (std::size_t i = 0; i < variants_.size(); ++i) variantIndex[variants_[i].label] = i;
    std::stable_sort(outcome_.rows.begin(), outcome_.rows.end(), [&](const StudyRow& a, const StudyRow& b) {
        return std::tuple(a.spp, variantIndex[a.variant], a.repeat) < std::tuple(b.spp, variantIndex[b.variant], b.repeat);
    });
}

// Repeat `rep` of a variant at spp (seed: the study's, the spp and the repeat number, the same for every
// variant: repeats are paired), measured into a row and the group's accumulators; false when cancelled.
bool StudyRun::renderRepeat(std::uint32_t spp, std::size_t ei, int rep, const Estimator& est) {
    const StudyVariant& variant = variants_[ei];
    RenderSettings rs = variantRenderSettings(c_, variant, spp);
    rs.cancel = cancel_;
    rs.seed = repeatSeed(c_.seed, spp, rep);
    const RenderResult r = rt_.render(scene_, *accel_, est, rs, &progress_.samples);
    progress_.finished(cost_[variant.label] * spp * c_.width * c_.height);
    if (r.cancelled) return false;
    if (!writer_) return true;  // it helped render; the writer measures
    const StudyRow row = measureRow(c_, scene_.name, variant, spp, rep, r, ref_);
    if (rep == 0 && (!c_.pageTopSppOnly || spp == c_.spps.back())) writer_->writeSppRender(variant.label, spp, r.image);
    if (spp == heatSpp_ && rep == 0) writer_->writeRender(variant.label, r.image, ref_);
    groups_[{spp, variant.label}].add(r.image);
    outcome_.rows.push_back(row);
    if (rowObserver()) rowObserver()(outcome_.rows.size());
    return true;
}

// The group columns of every row of (spp, variant): the bias from all its repeats' means, the pixel
// variance across the repeats whose images this run holds (kept rows of a resumed study keep theirs).
void StudyRun::refreshGroup(std::uint32_t spp, const std::string& label) {
    std::vector<std::size_t> idx;
    std::vector<MeanWithError> means;
    for (std::size_t i = 0; i < outcome_.rows.size(); ++i)
        if (outcome_.rows[i].spp == spp && outcome_.rows[i].variant == label) {
            idx.push_back(i);
            means.push_back({outcome_.rows[i].meanLuminance, outcome_.rows[i].meanStdError});
        }
    if (idx.empty()) return;
    const auto g = groups_.find({spp, label});
    const BiasEstimate bias = relativeBias(means, ref_.mean);
    for (std::size_t i : idx) {
        StudyRow& row = outcome_.rows[i];
        row.groupRelativeBias = bias.relative;
        row.groupBiasStdError = bias.stdError;
        row.groupBiasZ = bias.z;
        row.groupBiasThreshold = bias.threshold;
        row.groupBiasSignificant = bias.significant;
        if (g != groups_.end() && g->second.images >= 2) row.groupPixelVariance = g->second.pixelVariance();
        if (g != groups_.end() && g->second.firstBounce >= 0) row.groupFirstBounceVariance = g->second.firstBounce;
    }
}

// --target-interval: rounds of paired repeats at the top spp. Round by round, every variant that a
// comparison not yet settled needs renders its next repeat, until none does, --time would be passed by the
// next round, or a variant needing one more has --max-repeats.
void StudyRun::repeatUntilSettled() {
    const std::uint32_t top = c_.spps.back();
    const std::vector<VariantPair> comparisons = studyComparisons(variants_);
    double lastRound = 0;
    std::unique_ptr<ProgressBar> bar;
    std::atomic<int> settledCount{0};
    if (showProgress_ && writer_)
        bar = std::make_unique<ProgressBar>([&] { return static_cast<double>(settledCount.load()); }, static_cast<double>(comparisons.size()),
                                            [this] {
                                                std::lock_guard<std::mutex> lock(progress_.labelMutex);
                                                return progress_.label;
                                            },
                                            true);
    for (int round = 0;; ++round) {
        std::vector<std::size_t> next;
        std::string stop;
        if (writer_) {
            const std::set<std::string> need = variantsToRepeat(outcome_.rows, top, comparisons, c_.targetInterval);
            int open = 0;
            for (const VariantPair& cmp : comparisons) open += need.count(cmp.variant) || need.count(cmp.against) ? 1 : 0;
            settledCount = static_cast<int>(comparisons.size()) - open;
            bool atMost = false;
            for (std::size_t ei = 0; ei < variants_.size(); ++ei)
                if (need.count(variants_[ei].label)) {
                    if (repeatsOf(outcome_.rows, variants_[ei].label, top) >= c_.maxRepeats)
                        atMost = true;
                    else
                        next.push_back(ei);
                }
            const double elapsed = secondsSince(start_);
            if (need.empty())
                stop = "target";
            else if (next.empty() || atMost)
                stop = "max-repeats";
            else if (c_.timeLimit > 0 && elapsed + lastRound > c_.timeLimit)
                stop = "time";
        }
        // Every process renders the same round: the writer decides and tells the others.
        const int stopCode = rt_.writersInt(stop.empty() ? 0 : stop == "target" ? 1 : stop == "time" ? 2 : 3);
        if (stopCode != 0) {
            outcome_.stoppedBy = stopCode == 1 ? "target" : stopCode == 2 ? "time" : "max-repeats";
            break;
        }
        std::vector<int> list(next.begin(), next.end());
        list = rt_.writersInts(list);
        const auto roundStart = std::chrono::steady_clock::now();
        for (int ei : list) {
            const StudyVariant& v = variants_[static_cast<std::size_t>(ei)];
            const int rep = rt_.writersInt(writer_ ? repeatsOf(outcome_.rows, v.label, top) : 0);
            progress_.start(fmt::format("round {}: {} {} spp, repeat {} ({} variants in this round)", round + 1, v.label, top, rep + 1,
                                        list.size()),
                            cost_[v.label]);
            const auto est = makeEstimator(v.estimator, variantOptions(c_, v));
            if (!renderRepeat(top, static_cast<std::size_t>(ei), rep, *est)) {
                outcome_.cancelled = true;
                // Rows of a round are whole repeats: keep those finished (a resumed study keeps them too).
                break;
            }
            if (writer_) refreshGroup(top, v.label);
        }
        if (writer_) {
            orderRows();
            writer_->writeResults(outcome_, ref_);
        }
        if (outcome_.cancelled) {
            outcome_.stoppedBy = "cancelled";
            break;
        }
        lastRound = secondsSince(roundStart);
    }
    if (bar) bar->finish();
}

// The variance budget at the top spp: pairs of renders that differ only in the first bounce's numbers.
double StudyRun::budgetVariance(std::uint32_t spp, std::size_t ei, const Estimator& est) {
    const StudyVariant& variant = variants_[ei];
    double sum = 0;
    for (int b = 0; b < c_.budgetPairs && !outcome_.cancelled; ++b) {
        RenderSettings rs = variantRenderSettings(c_, variant, spp);
        rs.cancel = cancel_;
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
    start_ = std::chrono::steady_clock::now();
    showProgress_ = showProgress;
    prepare();
    const double total = plannedWork();
    rowCount_ = static_cast<int>(variants_.size() * c_.spps.size()) * c_.repeats;
    ProgressBar bar = progress_.bar(total, showProgress);
    if (!renderReference()) {
        bar.finish();
        outcome_.cancelled = true;
        return outcome_;
    }
    for (std::uint32_t spp : c_.spps)
        if (!runSpp(spp)) {
            outcome_.cancelled = true;
            break;
        }
    bar.finish();
    if (outcome_.cancelled)
        outcome_.stoppedBy = "cancelled";
    else if (c_.targetInterval > 0)
        repeatUntilSettled();
    outcome_.studySeconds = secondsSince(start_);
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
