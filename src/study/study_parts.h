// study/study_parts.h — the pieces of `symphong study`, shared among its files and not part of its
// interface (study.h): the plan (plan.cpp: checks, variants, the reference's cache key), the reference
// (reference.cpp), the measurement of a render against it (measure.cpp), the summary and conclusion
// (summary.cpp), the report and plots (report.cpp) and the writer of every file (writer.cpp); study.cpp runs them
// in order, and study/comparisons.h decides when its repeats are enough.
#pragma once

#include "io/image.h"
#include "render/checkpoint.h"
#include "compare/metrics.h"
#include "study/answer.h"
#include "study/study.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace symphong {

// ---- plan.cpp

/// Checks a study's configuration and puts its sample counts in order; returns the heat maps' spp.
std::uint32_t checkConfig(StudyConfig& c);
/// What the cached reference must match: scene (its file's content hash), size, spp, estimator, sampler,
/// depth, seed.
nlohmann::json referenceKey(const StudyConfig& c);
/// How the reference is rendered, as a variant's label would say it: its estimator, "+ears" when it splits.
std::string referenceMethod(const StudyConfig& c);
/// The seed of repeat `rep` at spp: the same for every variant (repeats are paired).
std::uint64_t repeatSeed(std::uint64_t seed, std::uint32_t spp, int rep);
/// The estimator options of a variant (its mode, its orbit).
EstimatorOptions variantOptions(const StudyConfig& c, const StudyVariant& v);
/// What every render of the study shares: its size, threads and depth (the reference's and the variants').
RenderSettings studyRenderSettings(const StudyConfig& c);
/// The settings of a variant's renders at `spp`: studyRenderSettings and the variant's sampler,
/// first-hit split and splitting (its repeats, variance budget and pilot all render with them); no seed, no
/// cancel.
RenderSettings variantRenderSettings(const StudyConfig& c, const StudyVariant& v, std::uint32_t spp);
/// The settings of the reference's render at `spp`: studyRenderSettings and the reference's sampler and
/// splitting; never a first-hit split nor the joint pattern (its key has neither); no seed, no cancel.
RenderSettings referenceRenderSettings(const StudyConfig& c, std::uint32_t spp);
/// Camera samples a pixel of the pilot render that estimates a variant's CPU time per camera sample for the
/// progress bar: 2, or ears::kProbeMinSpp x 2 for a variant that learns EARS factors, so that its probe runs
/// and its first epochs split as a render of the study would (on the smooth-sky scene sky-n10 it traces twice
/// phong's rays a sample at 16, 1.4 times at 2, where a 64-spp render of the study traces 3.3 times).
std::uint32_t pilotSpp(SplittingMode splitting);
/// The pilot's camera samples: kPilotSamples, or fewer in a study whose renders are smaller (as many as its
/// smallest render: the pilot costs no more than a repeat), but never under kPilotMinSide pixels a side. A
/// pilot of a millisecond or two was mostly the render's fixed start (its tracer, tiles and threads), which
/// pulled every variant's estimate towards the same cost.
inline constexpr std::uint64_t kPilotSamples = 16384;
inline constexpr int kPilotMinSide = 24;
/// The pilot of renders with settings `renders` (a variant's or the reference's): the same settings at
/// pilotSpp, on a square image of about the pilot's samples (at least kPilotMinSide pixels a side), seed 99.
RenderSettings pilotRenderSettings(const StudyConfig& c, RenderSettings renders);
/// The pilot of a variant: of variantRenderSettings.
RenderSettings pilotRenderSettings(const StudyConfig& c, const StudyVariant& v);

// ---- reference.cpp

/// The study's reference image with what is known of it.
struct Reference {
    Image image;
    MeanWithError mean;
    double noise = 0;   ///< mean over pixels of its variance-of-mean (luminance); 0 when unknown
    /// The standard deviation of its realized mean squared error about `noise`: sqrt(2 sum_p sigma_p^4) / P over
    /// its P pixels' variances-of-mean sigma_p^2, for pixel errors that are Gaussian (the mean of thousands of
    /// samples; heavier tails make it larger). Every render's MSE shares this error (study/measure.cpp); 0
    /// when unknown.
    double noiseSd = 0;
    std::string note;   ///< the report's sentence on where it came from
    bool have = false;  ///< false: it must be rendered
};

/// The given reference (--reference), or the one cached in `dir` for the same settings (`key`);
/// `have` false when there is none (a damaged cache counts as none).
Reference existingReference(const StudyConfig& c, const std::filesystem::path& dir, const nlohmann::json& key);

/// The reference from a render of it (`spp`: the samples it reached): its image rounded to 32-bit float as
/// the cache stores it (so a study gives the same numbers whether its reference was rendered or read
/// back), mean and noise.
Reference referenceFromRender(const StudyConfig& c, const RenderResult& r, std::uint32_t spp);

/// Writes reference.exr and reference.json (the cache) into dir.
void writeReferenceCache(const Reference& ref, const nlohmann::json& key, double seconds, const std::filesystem::path& dir);

// ---- resume.cpp

/// Seconds of render time between checkpoints of the study's reference.
inline constexpr double kStudyCheckpointInterval = 120;

/// The finished groups of rows of an earlier run of the study, by (spp, variant label).
using KeptGroups = std::map<std::pair<std::uint32_t, std::string>, std::vector<StudyRow>>;

/// The finished groups (all `repeats` rows) of dir/results.json; none when there is no such file (said
/// through `say`). An InputError naming the file when it cannot be read or was made with other settings
/// (the first that differs, of those that change rows: studyResultSettingsJson).
KeptGroups keptGroups(const StudyConfig& c, const std::filesystem::path& dir, const std::function<void(const std::string&)>& say);

/// The reference's state from its checkpoint at `path`, when there is one (an InputError when it is
/// damaged or of other settings).
void resumeReference(const std::filesystem::path& path, const RenderIdentity& identity, RenderState& state);

StudyRow rowFromJson(const nlohmann::json& j);

// ---- measure.cpp

/// One row: the render r of `variant` at spp, repeat `rep`, measured against the reference.
StudyRow measureRow(const StudyConfig& c, const std::string& sceneName, const StudyVariant& variant, std::uint32_t spp, int rep,
                    const RenderResult& r, const Reference& ref);

// ---- summary.cpp

nlohmann::json rowJson(const StudyRow& r);
nlohmann::json summaryJson(const StudySummary& s);
/// The summary of `estimator` (branch mode) under the same sampler as `like`, at the same spp.
const StudySummary* sameSampler(const std::vector<StudySummary>& s, const std::string& estimator, const StudySummary& like);
/// "2.3x", "15x".
std::string factor(double x);
/// Whether a variant is significantly biased at some spp.
/// The unbiased variant with the lowest RMSE at `spp` (none when there is no unbiased one).
const StudySummary* lowestRmse(const std::vector<StudySummary>& summary, std::uint32_t spp);

bool biasedAnywhere(const std::vector<StudySummary>& s, const std::string& variant);

// ---- report.cpp

struct Crop {
    int x, y, w, h;
};

/// What report.md is made of.
struct ReportInputs {
    const StudyConfig& config;
    std::string sceneName;
    const std::vector<StudySummary>& summary;
    const std::vector<StudyRow>& rows;
    std::string conclusion;
    const Reference& reference;
    bool plotted = false;
    std::uint32_t heatSpp = 0;
    bool cancelled = false;
    int processes = 1;
    const std::vector<std::string>& answer;  ///< studyAnswer's lines, computed once for report.md and report.html
    const std::vector<ReportTable>& tables;  ///< studyTables, the same
};

/// The report's words on the reference's own noise where it is at least half of the least MSE of `summary`:
/// how much of it each MSE still shares after its removal (Reference::noiseSd), which the efficiency
/// intervals include, as a warning to raise --reference-spp (or split the reference) above a tenth of that MSE; "" otherwise.
std::string referenceNoiseWords(const std::vector<StudySummary>& summary, const Reference& reference);
/// report.md: the answer (study/answer.h) and one table per measure.
std::string reportMarkdown(const ReportInputs& in);
/// details.md: the conclusion in words, the plots, the variance budget, every measure at equal samples, equal time.
std::string reportDetailsMarkdown(const ReportInputs& in);

/// Runs the embedded plotting script on dir with a python3 that has matplotlib; false (with a warning)
/// when there is none or the script fails.
bool makePlots(const StudyConfig& c, const std::filesystem::path& dir);

// ---- writer.cpp

/// What only the writing process holds: the output directory and every file the study writes.
class StudyWriter {
public:
    StudyWriter(const StudyConfig& c, const std::string& sceneName, std::uint32_t heatSpp, const std::vector<StudyVariant>& variants,
                int processes);
    /// The output directories and an empty results.csv (fails early when they cannot be written).
    void prepare() const;
    const std::filesystem::path& dir() const { return dir_; }
    /// A variant's first repeat at an spp, for report.html (half floats: what the page shows).
    void writeSppRender(const std::string& label, std::uint32_t spp, const Image& image) const;
    /// A variant's render at the heat maps' spp: its PNG and its relative error map.
    void writeRender(const std::string& label, const Image& image, const Reference& ref) const;
    /// results.csv and results.json with the rows so far, their summary, conclusion and comparisons.
    void writeResults(StudyOutcome& outcome, const Reference& ref) const;
    /// The last results, the plots, report.md, details.md and report.html.
    void finish(StudyOutcome& outcome, const Reference& ref) const;

private:
    const StudyConfig& c_;
    std::filesystem::path dir_;
    std::string sceneName_;
    std::uint32_t heatSpp_;
    const std::vector<StudyVariant>& variants_;
    int processes_;
};

/// The repeats' images of one group, as per-pixel sums of luminance and of its square (what the pixel
/// variance across repeats needs: compare/metrics.h's pixelVarianceAcrossRepeats, in the same order), and
/// its variance budget (measure.cpp).
struct GroupImages {
    std::vector<double> sum, sumSq;
    int images = 0;
    double firstBounce = -1;

    void add(const Image& image);
    /// The mean over pixels of the variance across the images (needs two).
    double pixelVariance() const;
};

// ---- study.cpp

/// The observer of setStudyRowObserver (empty by default).
std::function<void(std::size_t)>& rowObserver();

}  // namespace symphong
