// study/study.h — `symphong study`: renders a scene with several estimators at several sample counts,
// R independent times each, against a reference, and measures bias, RMSE, relMSE, per-pixel variance,
// time, rays and efficiency; writes results.csv, results.json, plots (through the embedded
// scripts/plot_study.py and matplotlib), heat maps, crops and report.md.
#pragma once

#include "estimators/estimator.h"
#include "render/progressive.h"
#include "render/renderer.h"

#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace symphong {

/// What a study's efficiency divides by: 1/(MSE x cost).
enum class StudyCost {
    Cpu,   ///< CPU seconds of the render's threads (summed over MPI ranks): what another program on the machine cannot bend
    Wall,  ///< wall-clock seconds: what a user waits, on this machine under its load at the time
    Rays,  ///< rays traced (closest-hit and shadow queries): a count, free of timing noise, blind to the cost of shading
};

/// "cpu", "wall", "rays".
std::string_view studyCostName(StudyCost cost);
/// Parses a cost's name; throws std::invalid_argument listing the valid ones.
StudyCost parseStudyCost(std::string_view name);

struct StudyConfig {
    std::string scene = "cornell";
    std::vector<std::string> estimators = {"cosine", "stratified", "phong", "symmetric", "symmetric-shifted", "paper"};
    std::vector<std::string> samplers = {std::string(kDefaultSampler)};  ///< every estimator runs under each
    std::vector<SymmetricMode> modes = {SymmetricMode::Branch};          ///< the set estimators run in each
    std::vector<std::uint32_t> spps = {1, 4, 16, 64};
    /// First-hit splitting (TraceSettings::firstHitSplit): each k > 1 adds a variant "+splitk" of every
    /// estimator of splitEstimators whose first hit takes one direction per call (spread mode for the set
    /// estimators), so a split estimator is compared with others split the same way.
    std::vector<int> splits;
    std::vector<std::string> splitEstimators = {"phong", "symmetric-mix"};
    /// --splittings: "none", "ears" and/or "ears-orbit"; with ears, every estimator of splitEstimators (that
    /// takes one direction per call) also runs with --splitting ears, a variant "+ears"; with ears-orbit,
    /// phong among them with --splitting ears-orbit, "+ears-orbit".
    std::vector<std::string> splittings = {"none"};
    /// Variance budget: this many pairs of renders of each variant at the top spp that differ only in the
    /// first bounce's random numbers (TraceSettings::firstBounceStream); half their squared difference,
    /// averaged, is the part of the pixel variance that comes from the first-bounce directions. 0: none.
    int budgetPairs = 0;
    bool jointFirstBounce = false;  ///< every render with TraceSettings::jointFirstBounce (the joint 4D pattern)
    /// `symmetric-mix` in branch mode: one variant "+orbitR" per R (copies of one point traced from one camera
    /// sample), each paired with `phong+splitR`; empty: the one orbit of options.symmetricOrbit.
    std::vector<int> orbits;
    /// Repeats of every variant at every spp; with targetInterval, the repeats before the first check.
    int repeats = 4;
    StudyCost cost = StudyCost::Cpu;
    /// > 0: at the top spp, add paired repeats (round r renders repeat r of each variant that needs it, seed r)
    /// until the 95% interval of every comparison of the answer (each unbiased variant against the yardstick,
    /// each fair pair) has a half-width of at most this fraction of its ratio and says ahead, behind or equal;
    /// or until timeLimit or maxRepeats.
    double targetInterval = 0;
    double timeLimit = 0;  ///< > 0: no repeat round starts that would end after this many seconds of the study
    int maxRepeats = 200;  ///< with targetInterval: the most repeats of any variant
    int width = 128, height = 128;
    int maxDepth = 16;
    std::uint64_t seed = 1;
    int threads = 0;
    std::string referencePath;          ///< a given reference EXR; empty: render (and cache) one
    std::uint32_t referenceSpp = 2048;  ///< with referenceError, the upper bound
    double referenceError = 0;          ///< > 0: the reference stops at this relative error of its mean
    std::string referenceEstimator = "phong";
    std::string referenceSampler = "independent";  ///< independent: the reference's own noise is then known
    /// How the reference's path vertices continue (render --splitting): "none", or "ears" / "ears-orbit" (unbiased,
    /// learned from the reference's own samples: less noise for its time where splitting pays, as on smooth skies)
    std::string referenceSplitting = "none";
    std::string outDir = "out/study";
    std::uint32_t heatmapSpp = 0;  ///< spp of the heat maps and crops; 0: the middle of `spps`
    bool pageTopSppOnly = false;   ///< report.html holds the renders of the top spp only (a smaller page)
    EstimatorOptions options;
    bool plots = true;
    bool page = true;  ///< write report.html (the page holds every render: a megabyte or more)
    /// Continue the study in outDir: keep the finished groups of rows of its results.json and resume
    /// its reference from reference.ckpt (both only when they are of this study's settings).
    bool resume = false;
    std::string python;  ///< interpreter for the plots; empty: /usr/bin/python3, then python3
};

/// What a study compares: an estimator, in a mode (set estimators), under a sampler. Its label names it
/// in tables and plots: the estimator, "+spread" in spread mode, "@sampler" when the study has several
/// samplers (not for `stratified`, bound to its own).
struct StudyVariant {
    std::string estimator, sampler, label;
    SymmetricMode mode = SymmetricMode::Branch;
    int split = 1;  ///< first-hit splitting: directions per camera sample at the first hit ("+splitk")
    int orbit = 0;  ///< estimators that take an orbit (`symmetric-mix`): its copies R; 0 for the others
    /// Paths each camera sample starts: split K, an orbit of R traced together (branch), or 1; 0 where it
    /// varies from hit to hit (the branch mode of the other set estimators). Fair pairs have equal counts.
    int pathsPerSample = 1;
    SplittingMode splitting = SplittingMode::None;  ///< "+ears", "+ears-orbit": render --splitting ears, ears-orbit
};

/// The variants of a configuration, estimator by estimator, in the order of the lists, without duplicates.
std::vector<StudyVariant> studyVariants(const StudyConfig& config);

/// One render: variant x spp x repeat. Group columns (group_*) repeat the (variant, spp) values.
struct StudyRow {
    std::string scene, estimator, variant, sampler, mode;
    std::uint32_t spp = 0;
    int split = 1;
    int repeat = 0;
    int width = 0, height = 0;
    double seconds = 0;     ///< wall time of the render
    double cpuSeconds = 0;  ///< CPU time of its threads (summed over ranks)
    double cost = 0;        ///< what efficiency divides by (StudyConfig::cost): seconds, cpuSeconds or rays
    std::uint64_t rays = 0, samples = 0, paths = 0;
    int orbit = 0;
    double meanLuminance = 0, meanStdError = 0;
    double relativeBias = 0;  ///< this render's image mean against the reference's
    double mseRaw = 0;        ///< mean squared luminance error against the reference
    double mse = 0;           ///< mseRaw less the reference's own noise (its mean variance), at least 0
    /// The standard deviation of the error that the reference's own noise leaves in `mse` (the realized
    /// noise less its mean): one error, the same in every row of a study (Reference::noiseSd); 0 when unknown.
    double referenceSd = 0;
    double rmse = 0, relMse = 0;
    double efficiency = 0;           ///< 1 / (mse * cost)
    double efficiencyRel = 0;        ///< 1 / (relMse * cost): weighs dark regions like bright ones
    double pixelVarianceWithin = 0;  ///< mean over pixels of the render's own variance-of-mean (luminance)
    // group values over the R repeats of (estimator, spp)
    double groupRelativeBias = 0, groupBiasStdError = 0, groupBiasZ = 0;
    double groupBiasThreshold = 4;  ///< |z| above which the group's bias counts as significant
    bool groupBiasSignificant = false;
    double groupPixelVariance = 0;  ///< mean over pixels of the variance across repeats (needs R >= 2)
    /// Mean over pixels of the variance that comes from the first-bounce directions (the variance budget,
    /// StudyConfig::budgetPairs); negative when not measured (other spp, or no pairs).
    double groupFirstBounceVariance = -1;
};

/// Aggregate of one (variant, spp) group: means over its repeats. A variant's efficiency is
/// 1/(mean MSE x mean cost), the inverse of the expected error times the expected cost (a median of
/// per-render efficiencies would hide the rare firefly render that a user pays for).
struct StudySummary {
    std::string estimator, variant, sampler, mode;
    std::uint32_t spp = 0;
    int repeats = 0;
    double seconds = 0, cpuSeconds = 0, cost = 0, rmse = 0, rmseSpread = 0, mse = 0, relMse = 0, efficiency = 0, efficiencyRel = 0;
    double rays = 0, paths = 0;
    double relativeBias = 0, biasStdError = 0, biasZ = 0;
    bool biasSignificant = false;
    double pixelVariance = 0;
    double firstBounceVariance = -1;  ///< the variance budget's first-bounce part (negative: not measured)
    /// Its share of the pixel variance across repeats (negative: not measured).
    double firstBounceShare() const { return firstBounceVariance >= 0 && pixelVariance > 0 ? firstBounceVariance / pixelVariance : -1.0; }
};

/// The CSV header, fixed: downstream scripts rely on these names and this order.
extern const char* const kStudyCsvHeader;
std::string studyCsv(const std::vector<StudyRow>& rows);

/// Groups rows by (variant, spp), in the order of first appearance; the mean over repeats of every measure,
/// efficiency from the means (StudySummary).
std::vector<StudySummary> summarizeStudy(const std::vector<StudyRow>& rows);

/// One paragraph answering, from the numbers: which variant wins where, and by what factor; each
/// estimator is compared with `cosine` and `phong` under the same sampler, and samplers with each other.
std::string studyConclusion(const std::vector<StudySummary>& summary, const std::vector<std::uint32_t>& spps);

struct StudyOutcome {
    std::vector<StudyRow> rows;
    std::vector<StudySummary> summary;
    bool cancelled = false;
    bool plotted = false;
    bool referenceRendered = false;  ///< false when the reference was given or taken from the cache
    int keptRows = 0;                ///< --resume: rows kept from the earlier run
    std::string conclusion;
    std::vector<std::string> answer;  ///< report.md's answer lines (study/answer.h), set when the report is written
    /// What ended the repeats at the top spp: "fixed" (no --target-interval), "target", "time", "max-repeats".
    std::string stoppedBy = "fixed";
    double studySeconds = 0;  ///< wall time of the whole study
};

/// Called after each finished row with the number of rows so far, in every runStudy of the process
/// (the command line's too); empty by default. Tests use it to stop a study at a known row.
void setStudyRowObserver(std::function<void(std::size_t rows)> observer);

/// Where a study's renders run and which process writes its files. This base class: all in this
/// process. A study shared among processes (distrib/study.h) runs runStudy in every process, in step:
/// each render is shared among them, the decisions taken from one process's files (a cached reference)
/// are made everyone's, and only that process (the writer) measures, writes and reports.
class StudyRuntime {
public:
    virtual ~StudyRuntime() = default;
    /// One of the study's renders (the reference and each row); collective when shared. The result is
    /// complete on the writer.
    virtual RenderResult render(const Scene& scene, const Accel& accel, const Estimator& estimator, const RenderSettings& settings,
                                std::atomic<std::uint64_t>* progress) const;
    /// Collective: every process passes the bad-input error it met while preparing ("" if none); returns
    /// the first one of all processes, the same everywhere ("" when none failed).
    virtual std::string agreeOnError(const std::string& localError) const { return localError; }
    /// Collective: the writer's value, on every process.
    virtual bool writersValue(bool value) const { return value; }
    virtual int writersInt(int value) const { return value; }
    virtual std::vector<int> writersInts(std::vector<int> values) const { return values; }
    virtual bool writer() const { return true; }
    /// The reference in passes (render/progressive.h) until `rules` stop it; collective when shared: the
    /// writer runs the passes and `afterPass` (its checkpoints) and returns why they stopped, the others
    /// render each pass with it (their `state` is scratch).
    virtual StopReason renderPasses(const Scene& scene, const Accel& accel, const Estimator& estimator, const RenderSettings& settings,
                                    const StopRules& rules, RenderState& state, const std::function<void(const PassReport&)>& afterPass,
                                    std::atomic<std::uint64_t>* progress) const;
    virtual int processes() const { return 1; }
};

/// Runs the study; `cancel` (e.g. set by Ctrl-C) stops it between tiles, keeping finished rows in
/// results.csv. Throws InputError on bad configuration. `runtime` null: all in this process.
StudyOutcome runStudy(const StudyConfig& config, const std::atomic<bool>* cancel = nullptr, bool showProgress = false,
                      const StudyRuntime* runtime = nullptr);

}  // namespace symphong
