// The study's writer: what only the writing process does, every file the study writes into its output
// directory (results.csv and results.json as rows arrive, the renders report.html shows, the heat maps,
// and at the end the plots, report.md, details.md and report.html).
#include "study/report_html.h"
#include "study/study_parts.h"

#include "io/files.h"
#include "io/input_error.h"
#include "study/config.h"

#include <fmt/format.h>

#include <algorithm>

namespace fs = std::filesystem;

namespace symphong {

StudyWriter::StudyWriter(const StudyConfig& c, const std::string& sceneName, std::uint32_t heatSpp, const std::vector<StudyVariant>& variants,
                         int processes)
    : c_(c), dir_(c.outDir), sceneName_(sceneName), heatSpp_(heatSpp), variants_(variants), processes_(processes) {}

void StudyWriter::prepare() const {
    std::error_code ec;
    fs::create_directories(dir_ / "renders", ec);
    fs::create_directories(dir_ / "heatmaps", ec);
    if (ec || !fs::is_directory(dir_)) throw InputError(fmt::format("--out {}: cannot create the directory", c_.outDir));
    writeFile((dir_ / "results.csv").string(), std::string(kStudyCsvHeader) + "\n");
}

void StudyWriter::writeSppRender(const std::string& label, std::uint32_t spp, const Image& image) const {
    writeExr(image, sppRenderPath(dir_, label, spp).string(), true);
}

void StudyWriter::writeRender(const std::string& label, const Image& image, const Reference& ref) const {
    writePng(image, (dir_ / "renders" / (label + ".png")).string());
    const std::vector<float> map = relativeErrorMap(image, ref.image);
    writeFile((dir_ / "heatmaps" / (label + ".f32")).string(),
              std::string(reinterpret_cast<const char*>(map.data()), map.size() * sizeof(float)));
}

void StudyWriter::writeResults(StudyOutcome& outcome, const Reference& ref) const {
    writeFile((dir_ / "results.csv").string(), studyCsv(outcome.rows));
    nlohmann::json variantList = nlohmann::json::array();
    for (const auto& v : variants_)
        variantList.push_back({{"label", v.label},
                               {"estimator", v.estimator},
                               {"sampler", v.sampler},
                               {"mode", symmetricModeName(v.mode)},
                               {"split", v.split}});
    const Crop crop{c_.width / 3, c_.height / 3, std::max(1, c_.width / 3), std::max(1, c_.height / 3)};
    nlohmann::json j;
    j["config"] = {
        {"scene", sceneName_},
        {"scene_spec", c_.scene},
        {"estimators", c_.estimators},
        {"samplers", c_.samplers},
        {"variants", variantList},
        {"spp", c_.spps},
        {"symmetric_orbit", c_.options.symmetricOrbit},
        {"orbits", c_.orbits},
        {"cost", studyCostName(c_.cost)},
        {"target_interval", c_.targetInterval},
        {"time", c_.timeLimit},
        {"max_repeats", c_.maxRepeats},
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
          {"splitting", c_.referenceSplitting},
          {"spp", c_.referenceSpp},
          {"mean_luminance", ref.mean.mean},
          {"pixel_variance", ref.noise},
          {"noise_sd", ref.noiseSd}}},
        {"heatmap", {{"spp", heatSpp_}, {"width", c_.width}, {"height", c_.height}, {"crop", {crop.x, crop.y, crop.w, crop.h}}}}};
    j["settings"] = studySettingsJson(c_);
    j["rows"] = nlohmann::json::array();
    for (const auto& r : outcome.rows) j["rows"].push_back(rowJson(r));
    outcome.summary = summarizeStudy(outcome.rows);
    j["summary"] = nlohmann::json::array();
    for (const auto& s : outcome.summary) j["summary"].push_back(summaryJson(s));
    outcome.conclusion = studyConclusion(outcome.summary, c_.spps);
    j["conclusion"] = outcome.conclusion;
    j["comparisons"] = answerComparisonsJson(c_, outcome.rows, outcome.summary);
    j["stopped_by"] = outcome.stoppedBy;
    j["study_seconds"] = outcome.studySeconds;
    writeFile((dir_ / "results.json").string(), j.dump(1) + "\n");
}

void StudyWriter::finish(StudyOutcome& outcome, const Reference& ref) const {
    writeResults(outcome, ref);
    if (!outcome.cancelled && c_.plots) outcome.plotted = makePlots(c_, dir_);
    // The answer and tables, once for report.md, report.html and the command line.
    outcome.answer = studyAnswer(c_, outcome.rows, outcome.summary, {outcome.stoppedBy, c_.targetInterval});
    const std::vector<ReportTable> tables = studyTables(c_, outcome.rows, outcome.summary);
    const ReportInputs in{c_,        sceneName_,        outcome.summary, outcome.rows,   outcome.conclusion, ref, outcome.plotted,
                          heatSpp_, outcome.cancelled, processes_,      outcome.answer, tables};
    writeFile((dir_ / "report.md").string(), reportMarkdown(in));
    writeFile((dir_ / "details.md").string(), reportDetailsMarkdown(in));
    // Not when interrupted: its FLIP maps take seconds that a job stopped by its launcher does not have
    // (mpirun kills the ranks a second after SIGTERM); the resumed study writes it.
    std::error_code ec;
    if (outcome.cancelled || !c_.page)
        fs::remove(dir_ / "report.html", ec);  // an earlier run's page would not match these rows
    else
        writeFile((dir_ / "report.html").string(), reportHtml(reportHtmlData(in, dir_)));
}

}  // namespace symphong
