#include "study/config.h"

#include "estimators/options.h"
#include "io/input_error.h"
#include "render/settings.h"
#include "study/environment.h"

#include <fmt/format.h>

#include <algorithm>

namespace symphong {

namespace {

std::vector<std::string> modeNames() { return {"branch", "spread"}; }

/// The reference's fields: given, or rendered with its spp, error, estimator and sampler.
void addReferenceFields(schema::Schema<StudyOptions>& s) {
    using F = schema::Field<StudyOptions>;
    using schema::ref;
    using O = StudyOptions;
    s.push_back(F("reference", "--reference", "reference image (linear EXR of the same size) instead of rendering one",
                  ref<O>([](O & o) -> auto& { return o.config.referencePath; }))
                    .noDefaultShown()
                    .orNone());
    s.push_back(F("reference_spp", "--reference-spp", "samples per pixel of the rendered reference",
                  ref<O>([](O & o) -> auto& { return o.config.referenceSpp; }))
                    .range(1, 10000000));
    s.push_back(F("reference_error", "--reference-error",
                  "stop the rendered reference once the relative standard error of its mean is at most this (e.g. 0.001), "
                  "with --reference-spp as the upper bound; 0: exactly --reference-spp",
                  ref<O>([](O & o) -> auto& { return o.config.referenceError; }))
                    .range(0, 1));
    s.push_back(F("reference_estimator", "--reference-estimator", "unbiased estimator for the reference",
                  ref<O>([](O & o) -> auto& { return o.config.referenceEstimator; })));
    s.push_back(F("reference_sampler", "--reference-sampler", "sampler of the reference (independent: its own noise is known)",
                  ref<O>([](O & o) -> auto& { return o.config.referenceSampler; }))
                    .namedFrom(samplerNames)
                    .checkedBy(checkSamplerName));
    s.push_back(F("reference_splitting", "--reference-splitting",
                  "how the reference's path vertices continue, as render --splitting: none, or ears (Russian roulette and "
                  "splitting learned from the reference's own samples: unbiased, and less noise for its time where splitting "
                  "pays: 1.6x the efficiency of a plain reference on the smooth-sky scene sky-n10; README \"The reference's own noise\")",
                  ref<O>([](O & o) -> auto& { return o.config.referenceSplitting; }))
                    .namedFrom(splittingNames)
                    .checkedBy(checkSplittingName));
}

/// First-hit splitting and --splittings: which variants split, and how.
void addSplitFields(schema::Schema<StudyOptions>& s) {
    using F = schema::Field<StudyOptions>;
    using schema::ref;
    using O = StudyOptions;
    s.push_back(F("splits", "--splits",
                  "first-hit splitting: for each K > 1 also run every estimator of --split-estimators with K directions per "
                  "camera sample from its first hit (a variant '+splitK'), comma-separated",
                  ref<O>([](O & o) -> auto& { return o.config.splits; }))
                    .range(1, 64)
                    .noDefaultShown());
    s.push_back(F("split_estimators", "--split-estimators", "the estimators that --splits applies to, comma-separated",
                  schema::member(&O::splitEstimators))
                    .listOfNames());
    s.push_back(F("splittings", "--splittings",
                  "none, ears and/or ears-orbit, comma-separated: with ears, every estimator of --split-estimators also renders "
                  "with render --splitting ears (a variant '+ears': Russian roulette and splitting learned from its own samples); "
                  "with ears-orbit, phong (if among them) with --splitting ears-orbit ('+ears-orbit', compared with '+ears' too)",
                  schema::member(&O::splittings))
                    .listOfNames());
}

/// The variants' orbits, the repeats, the cost and the rule that adds repeats.
void addRepeatFields(schema::Schema<StudyOptions>& s) {
    using F = schema::Field<StudyOptions>;
    using schema::ref;
    using O = StudyOptions;
        s.push_back(F("orbits", "--orbits",
                      "symmetric-mix in branch mode: one variant per R (R symmetric copies of one point traced from each camera sample, "
                      "'+orbitR'), each compared with phong split R ways (--splits R): 1, 2, 4 or 8, comma-separated",
                      ref<O>([](O & o) -> auto& { return o.config.orbits; }))
                        .range(1, 8)
                        .noDefaultShown());
        s.push_back(F("repeats", "--repeats,-R",
                      "independent renders per estimator and spp (paired: repeat r of every variant has seed r); with "
                      "--target-interval, the repeats before the first check",
                      ref<O>([](O & o) -> auto& { return o.config.repeats; }))
                        .range(1, 1000));
        s.push_back(F("cost", "--cost",
                      "what efficiency 1/(MSE x cost) divides by: 'cpu' (CPU seconds of the render's threads, summed over MPI ranks: "
                      "other programs on the machine cannot bend it), 'wall' (wall-clock seconds) or 'rays' (rays traced) [default: cpu]",
                      schema::TextAccess<O>{[](const O& o) { return std::string(studyCostName(o.config.cost)); },
                                            [](O& o, const std::string& name) { o.config.cost = parseStudyCost(name); }})
                        .type("COST"));
        s.push_back(F("target_interval", "--target-interval",
                      "add paired repeats at the top spp until every comparison of the answer (each variant against phong, each fair "
                      "pair) has a 95% interval whose half-width is at most this fraction of its ratio and that says ahead, behind or "
                      "equal (e.g. 0.1); 0: exactly --repeats",
                      ref<O>([](O & o) -> auto& { return o.config.targetInterval; }))
                        .range(0, 10)
                        .keepsPixels());
        s.push_back(F("time", "--time",
                      "with --target-interval: start no round of repeats that would end after this many seconds of the study "
                      "(0: no limit)",
                      ref<O>([](O & o) -> auto& { return o.config.timeLimit; }))
                        .range(0, 1e9)
                        .keepsPixels());
        s.push_back(F("max_repeats", "--max-repeats", "with --target-interval: the most repeats of any variant",
                      ref<O>([](O & o) -> auto& { return o.config.maxRepeats; }))
                        .range(2, 100000)
                        .keepsPixels());
}

}  // namespace

const schema::Schema<StudyOptions>& studySchema() {
    using F = schema::Field<StudyOptions>;
    using schema::kCli;
    using schema::ref;
    using O = StudyOptions;
    static const schema::Schema<StudyOptions> fields = [] {
        schema::Schema<StudyOptions> s;
        s.push_back(F("scene", "scene", "cornell, FILE.obj or FILE.json", ref<O>([](O & o) -> auto& { return o.config.scene; }))
                        .only(schema::kCli | schema::kJson));
        s.push_back(
            F("estimators", "--estimators,-e", "estimators, comma-separated, or all", schema::member(&O::estimators)).listOfNames());
        s.push_back(
            F("samplers", "--samplers", "samplers, comma-separated, or all: every estimator runs under each", schema::member(&O::samplers))
                .listOfNames());
        s.push_back(F("symmetric_modes", "--symmetric-modes", "modes of paper and symmetric*, comma-separated: branch, spread, or all",
                      schema::member(&O::modes))
                        .listOfNames());
        s.push_back(F("spp", "--spp", "samples per pixel, comma-separated", schema::member(&O::spps)).range(1, 1000000));
        addSplitFields(s);
        s.push_back(F("budget_pairs", "--budget-pairs",
                      "variance budget: pairs of renders per variant at the top spp that differ only in the first bounce's random "
                      "numbers; the report gives the first bounce's share of the pixel variance (0: none)",
                      ref<O>([](O & o) -> auto& { return o.config.budgetPairs; }))
                        .range(0, 64));
        s.push_back(F("joint_first_bounce", "--joint-first-bounce",
                      "every render with the pixel position and the first bounce from one 4D Sobol' pattern (render --joint-first-bounce)",
                      ref<O>([](O & o) -> auto& { return o.config.jointFirstBounce; })));
        addRepeatFields(s);
        addReferenceFields(s);
        s.push_back(F("out", "--out,-o", "output directory", ref<O>([](O & o) -> auto& { return o.config.outDir; })).keepsPixels());
        s.push_back(F("width", "--width,-W", "image width", ref<O>([](O & o) -> auto& { return o.config.width; })).range(1, 4096));
        s.push_back(F("height", "--height,-H", "image height", ref<O>([](O & o) -> auto& { return o.config.height; })).range(1, 4096));
        s.push_back(
            F("max_depth", "--max-depth,-d", "most scattering events per path", ref<O>([](O & o) -> auto& { return o.config.maxDepth; }))
                .range(0, 1024));
        s.push_back(F("seed", "--seed", "random seed", ref<O>([](O & o) -> auto& { return o.config.seed; })));
        s.push_back(F("threads", "--threads,-t", "worker threads, 0 = all cores", ref<O>([](O & o) -> auto& { return o.config.threads; }))
                        .range(0, 4096)
                        .keepsPixels());
        s.push_back(F("heatmap_spp", "--heatmap-spp", "spp of the heat maps and crops (default: the middle --spp value)",
                      ref<O>([](O & o) -> auto& { return o.config.heatmapSpp; }))
                        .range(0, 1000000)
                        .noDefaultShown());
        s.push_back(F("page_top_spp_only", "--page-top-spp-only",
                      "report.html holds each variant's render at the top spp only, not at every spp (a page a fraction of the size)",
                      ref<O>([](O & o) -> auto& { return o.config.pageTopSppOnly; }))
                        .keepsPixels());
        s.push_back(F("python", "--python", "python3 with matplotlib for the plots (default: /usr/bin/python3, then python3)",
                      ref<O>([](O & o) -> auto& { return o.config.python; }))
                        .noDefaultShown()
                        .orNone()
                        .keepsPixels());
        s.push_back(F("no_plots", "--no-plots", "skip the plots", schema::member(&O::noPlots)).python("plots", true).keepsPixels());
        s.push_back(F("no_page", "--no-page", "skip report.html (report.md, details.md and the results are written)",
                      schema::member(&O::noPage))
                        .python("page", true)
                        .keepsPixels());
        s.push_back(F("resume", "--resume",
                      "continue the study in --out: keep the finished groups of rows of its results.json and resume its reference "
                      "from reference.ckpt (refused when they are of other settings)",
                      ref<O>([](O & o) -> auto& { return o.config.resume; }))
                        .keepsPixels());
        // The estimators' parameters, but not --symmetric-mode: each mode is a variant of its own (--symmetric-modes).
        for (auto& f : schema::nested(schema::nested(estimatorOptionsSchema(), &StudyConfig::options, {"symmetric_mode"}), &O::config))
            s.push_back(std::move(f));
        return s;
    }();
    return fields;
}

const schema::Schema<FurnaceOptions>& furnaceSchema() {
    using F = schema::Field<FurnaceOptions>;
    using schema::ref;
    using O = FurnaceOptions;
    static const schema::Schema<FurnaceOptions> fields = [] {
        schema::Schema<FurnaceOptions> s;
        s.push_back(F("estimators", "--estimator,-e", "estimators, comma-separated, or all", schema::member(&O::estimators)).listOfNames());
        s.push_back(
            F("environments", "--environment", "environments, comma-separated, or all", schema::member(&O::environments)).listOfNames());
        s.push_back(F("rho_d", "--rho-d", "diffuse albedo", ref<O>([](O & o) -> auto& { return o.table.rhoD; })).range(0.0, 1.0));
        s.push_back(F("rho_s", "--rho-s", "specular albedo", ref<O>([](O & o) -> auto& { return o.table.rhoS; })).range(0.0, 1.0));
        s.push_back(F("n", "--n", "Phong exponents", ref<O>([](O & o) -> auto& { return o.table.exponents; }))
                        .range(0.0, 1e6)
                        .rangeOnCommandLineOnly());
        s.push_back(F("theta", "--theta", "view angles from the normal, degrees", ref<O>([](O & o) -> auto& { return o.table.thetas; }))
                        .range(0.0, 89.9)
                        .rangeOnCommandLineOnly());
        s.push_back(F("phi", "--phi", "view azimuth, degrees", ref<O>([](O & o) -> auto& { return o.table.phiDeg; })).range(-360.0, 360.0));
        s.push_back(F("repeats", "--repeats,-M", "independent estimates", ref<O>([](O & o) -> auto& { return o.table.repeats; }))
                        .range(2, 100000000));
        s.push_back(F("seed", "--seed", "random seed", ref<O>([](O & o) -> auto& { return o.table.seed; })));
        s.push_back(F("sampler", "--sampler", "sample generator: " + fmt::format("{}", fmt::join(samplerNames(), ", ")),
                      ref<O>([](O & o) -> auto& { return o.table.sampler; }))
                        .namedFrom(samplerNames)
                        .checkedBy(checkSamplerName));
        s.push_back(F("directions", "--directions", "calls per estimate for one-direction estimators",
                      ref<O>([](O & o) -> auto& { return o.table.directions; }))
                        .range(1, 1000000));
        s.push_back(F("disk_theta", "--disk-theta", "disk light: polar angle, degrees",
                      ref<O>([](O & o) -> auto& { return o.table.environment.diskTheta; }))
                        .range(0.0, 180.0));
        s.push_back(
            F("disk_phi", "--disk-phi", "disk light: azimuth, degrees", ref<O>([](O & o) -> auto& { return o.table.environment.diskPhi; }))
                .range(-360.0, 360.0));
        s.push_back(F("disk_radius", "--disk-radius", "disk light: angular radius, degrees",
                      ref<O>([](O & o) -> auto& { return o.table.environment.diskRadius; }))
                        .range(0.01, 89.9));
        s.push_back(
            F("band", "--band", "horizon band height, degrees", ref<O>([](O & o) -> auto& { return o.table.environment.bandDegrees; }))
                .range(0.01, 90.0));
        s.push_back(F("grid", "--grid", "n in {1,10,100,1000,10000} x theta in {0,30,60,85}", schema::member(&O::grid)));
        s.push_back(F("json", "--json", "also write the results as JSON to this file", schema::member(&O::json))
                        .only(schema::kCli)
                        .noDefaultShown());
        for (auto& f : schema::nested(schema::nested(estimatorOptionsSchema(), &FurnaceTable::options), &O::table))
            s.push_back(std::move(f));
        return s;
    }();
    return fields;
}

std::vector<std::string> nameList(const std::string& text, const std::vector<std::string>& all, const char* what, bool validate) {
    if (text == "all") return all;
    std::vector<std::string> out;
    std::size_t start = 0;
    while (start <= text.size()) {
        const auto comma = text.find(',', start);
        std::string item = text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
        if (validate && std::find(all.begin(), all.end(), item) == all.end())
            throw InputError(fmt::format("{}: unknown name '{}' (valid: {}, or all)", what, item, fmt::join(all, ", ")));
        out.push_back(item);
        if (comma == std::string::npos) break;
        start = comma + 1;
    }
    return out;
}

StudyConfig toStudyConfig(const StudyOptions& o, bool validateNames) {
    StudyConfig c = o.config;
    c.estimators = nameList(o.estimators, estimatorNames(), "--estimators", validateNames);
    c.samplers = nameList(o.samplers, samplerNames(), "--samplers", validateNames);
    c.modes.clear();
    for (const std::string& m : nameList(o.modes, modeNames(), "--symmetric-modes", validateNames)) try {
            c.modes.push_back(parseSymmetricMode(m));
        } catch (const std::invalid_argument& e) {
            throw InputError(fmt::format("symmetric_modes: {}", e.what()));
        }
    c.spps = o.spps;
    c.splitEstimators = nameList(o.splitEstimators, estimatorNames(), "--split-estimators", validateNames);
    c.splittings = nameList(o.splittings, splittingNames(), "--splittings", true);
    c.plots = !o.noPlots;
    c.page = !o.noPage;
    return c;
}

StudyOptions studyOptionsOf(const StudyConfig& c) {
    StudyOptions o;
    o.config = c;
    o.estimators = fmt::format("{}", fmt::join(c.estimators, ","));
    o.samplers = fmt::format("{}", fmt::join(c.samplers, ","));
    std::vector<std::string> modes;
    for (SymmetricMode m : c.modes) modes.emplace_back(symmetricModeName(m));
    o.modes = fmt::format("{}", fmt::join(modes, ","));
    o.spps = c.spps;
    o.splitEstimators = fmt::format("{}", fmt::join(c.splitEstimators, ","));
    o.splittings = fmt::format("{}", fmt::join(c.splittings, ","));
    o.noPlots = !c.plots;
    o.noPage = !c.page;
    return o;
}

std::string studyCommandLine(const StudyConfig& c) {
    // The lists and the size always, as the reports have always shown them; every other option where it is not the default.
    return schema::commandLine(studyOptionsOf(c), studySchema(),
                               {"scene", "estimators", "samplers", "symmetric_modes", "spp", "repeats", "width", "height"});
}

nlohmann::json studySettingsJson(const StudyConfig& c) { return schema::toJson(studyOptionsOf(c), studySchema()); }

nlohmann::json studyResultSettingsJson(const StudyConfig& c) { return schema::pixelSettingsJson(studyOptionsOf(c), studySchema()); }

FurnaceTable toFurnaceTable(const FurnaceOptions& o, bool validateNames) {
    FurnaceTable t = o.table;
    t.estimators = nameList(o.estimators, estimatorNames(), "--estimator", validateNames);
    t.environments = nameList(o.environments, environmentNames(), "--environment", validateNames);
    if (o.grid) t.exponents = furnaceGridExponents(), t.thetas = furnaceGridThetas();
    return t;
}

}  // namespace symphong
