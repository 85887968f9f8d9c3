// The study's plan: its configuration checked, its variants, and the key its cached reference must match.
#include "estimators/registry.h"
#include "io/files.h"
#include "io/input_error.h"
#include "sampling/rng.h"
#include "sampling/sampler_registry.h"
#include "splitting/learning.h"
#include "study/study_parts.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

namespace fs = std::filesystem;

namespace symphong {

namespace {

std::string sceneFingerprint(const std::string& spec) {
    if (spec == "cornell" || !fs::exists(spec)) return spec;
    const std::string text = readTextFile(spec);
    return fmt::format("{}:{:016x}", spec, std::hash<std::string>{}(text));
}

}  // namespace

std::string_view studyCostName(StudyCost cost) {
    switch (cost) {
        case StudyCost::Cpu: return "cpu";
        case StudyCost::Wall: return "wall";
        case StudyCost::Rays: return "rays";
    }
    return "cpu";
}

StudyCost parseStudyCost(std::string_view name) {
    for (StudyCost c : {StudyCost::Cpu, StudyCost::Wall, StudyCost::Rays})
        if (studyCostName(c) == name) return c;
    throw std::invalid_argument(fmt::format("unknown cost '{}' (valid: cpu, wall, rays)", name));
}

std::vector<StudyVariant> studyVariants(const StudyConfig& c) {
    std::vector<StudyVariant> out;
    for (const std::string& e : c.estimators) {
        const auto probe = makeEstimator(e, c.options);
        const bool set = hasSymmetricModes(e);
        const EstimatorEntry* entry = findEstimator(e);
        const bool takesOrbit = entry && entry->traits.takesOrbit;
        std::vector<int> splits{1};
        if (std::find(c.splitEstimators.begin(), c.splitEstimators.end(), e) != c.splitEstimators.end())
            for (int k : c.splits)
                if (k > 1) splits.push_back(k);
        for (SymmetricMode mode : set ? c.modes : std::vector<SymmetricMode>{SymmetricMode::Branch}) {
            // --orbits: one variant per orbit in branch mode ("+orbitR"); otherwise the one orbit of the options.
            std::vector<int> orbits{takesOrbit ? c.options.symmetricOrbit : 0};
            const bool orbitVariants = takesOrbit && mode == SymmetricMode::Branch && !c.orbits.empty();
            if (orbitVariants) orbits = c.orbits;
            for (int orbit : orbits)
                for (int split : splits) {
                    // A branch-mode set already traces many directions from its first hit: not split further.
                    EstimatorOptions o = c.options;
                    o.symmetricMode = mode;
                    if (orbit > 0) o.symmetricOrbit = orbit;
                    const auto made = makeEstimator(e, o);
                    if (split > 1 && made->returnsSets()) continue;
                    for (const std::string& sampler : c.samplers) {
                        StudyVariant v;
                        v.estimator = e;
                        v.mode = mode;
                        v.split = split;
                        v.orbit = orbit;
                        v.pathsPerSample = split > 1                                        ? split
                                           : takesOrbit && mode == SymmetricMode::Branch ? orbit
                                           : made->returnsSets()                           ? 0
                                                                                           : 1;
                        v.sampler = effectiveSampler(*probe, sampler);
                        v.label = e + (set && mode == SymmetricMode::Spread ? "+spread" : "") +
                                  (orbitVariants ? fmt::format("+orbit{}", orbit) : "") + (split > 1 ? fmt::format("+split{}", split) : "");
                        if (c.samplers.size() > 1 && probe->requiredSampler().empty()) v.label += "@" + v.sampler;
                        if (std::none_of(out.begin(), out.end(), [&](const StudyVariant& o) { return o.label == v.label; }))
                            out.push_back(v);
                        // --splittings ears, ears-orbit: the unsplit one-direction variants of --split-estimators once more,
                        // learning (ears-orbit only for phong, whose density its orbits have).
                        const bool splits = std::find(c.splitEstimators.begin(), c.splitEstimators.end(), e) != c.splitEstimators.end();
                        for (const std::string& name : c.splittings) {
                            const SplittingMode mode = splittingMode(name);
                            if (!learnsFactors(mode) || !splits || split != 1 || made->returnsSets()) continue;
                            if (mode == SplittingMode::EarsOrbit && e != "phong") continue;
                            StudyVariant w = v;
                            w.splitting = mode;
                            w.pathsPerSample = 0;  // it varies from vertex to vertex
                            const std::size_t at = v.label.find('@');
                            w.label = v.label.substr(0, at) + "+" + name + (at == std::string::npos ? "" : v.label.substr(at));
                            if (std::none_of(out.begin(), out.end(), [&](const StudyVariant& o) { return o.label == w.label; }))
                                out.push_back(w);
                        }
                    }
                }
        }
    }
    return out;
}

std::uint64_t repeatSeed(std::uint64_t seed, std::uint32_t spp, int rep) {
    return mixSeed(mixSeed(mixSeed(seed, 0x5EED), spp), static_cast<std::uint64_t>(rep));
}

/// Checks a study's configuration and puts its sample counts in order; returns the heat maps' spp.
std::uint32_t checkConfig(StudyConfig& c) {
    if (c.estimators.empty()) throw InputError("--estimators: the list is empty");
    for (const auto& e : c.estimators) try {
            makeEstimator(e, c.options);
        } catch (const std::invalid_argument& err) {
            throw InputError(fmt::format("--estimators: {}", err.what()));
        }
    try {
        makeEstimator(c.referenceEstimator, c.options);
    } catch (const std::invalid_argument& err) {
        throw InputError(fmt::format("--reference-estimator: {}", err.what()));
    }
    if (!estimatorEntry(c.referenceEstimator).traits.hasDensity)
        throw InputError(fmt::format("--reference-estimator: '{}' is biased; choose an unbiased estimator", c.referenceEstimator));
    if (splittingMode(c.referenceSplitting) == SplittingMode::EarsOrbit && c.referenceEstimator != "phong")
        throw InputError(
            fmt::format("--reference-splitting ears-orbit: needs --reference-estimator phong (its orbits are of phong's "
                        "lobe), not '{}'",
                        c.referenceEstimator));
    if (c.samplers.empty()) throw InputError("--samplers: the list is empty");
    for (const auto& name : c.samplers)
        if (std::find(samplerNames().begin(), samplerNames().end(), name) == samplerNames().end())
            throw InputError(fmt::format("--samplers: unknown sampler '{}' (valid: {})", name, fmt::join(samplerNames(), ", ")));
    if (c.modes.empty()) throw InputError("--symmetric-modes: the list is empty");
    if (c.spps.empty()) throw InputError("--spp: the list is empty");
    for (auto s : c.spps)
        if (s == 0) throw InputError("--spp: sample counts must be at least 1");
    std::sort(c.spps.begin(), c.spps.end());
    c.spps.erase(std::unique(c.spps.begin(), c.spps.end()), c.spps.end());
    if (c.repeats < 1) throw InputError(fmt::format("--repeats {} must be at least 1", c.repeats));
    if (c.targetInterval < 0 || !std::isfinite(c.targetInterval))
        throw InputError(fmt::format("--target-interval {} must be a finite number >= 0", c.targetInterval));
    if (c.targetInterval > 0 && c.repeats < 2)
        throw InputError(fmt::format("--target-interval needs --repeats of at least 2 (got {}): an interval needs two repeats", c.repeats));
    if (c.targetInterval > 0 && c.maxRepeats < c.repeats)
        throw InputError(fmt::format("--max-repeats {} is less than --repeats {}", c.maxRepeats, c.repeats));
    if (c.timeLimit < 0 || !std::isfinite(c.timeLimit)) throw InputError(fmt::format("--time {} must be a finite number >= 0", c.timeLimit));
    for (int r : c.orbits)
        if (r != 1 && r != 2 && r != 4 && r != 8) throw InputError(fmt::format("--orbits: {} is not one of 1, 2, 4, 8", r));
    for (int k : c.splits)
        if (k < 1 || k > 64) throw InputError(fmt::format("--splits: {} is out of range (1..64)", k));
    for (const auto& e : c.splitEstimators)
        if (std::find(estimatorNames().begin(), estimatorNames().end(), e) == estimatorNames().end())
            throw InputError(fmt::format("--split-estimators: unknown estimator '{}' (valid: {})", e, fmt::join(estimatorNames(), ", ")));
    if (c.budgetPairs < 0 || c.budgetPairs > 64) throw InputError(fmt::format("--budget-pairs {} is out of range (0..64)", c.budgetPairs));
    const std::uint32_t heatSpp = c.heatmapSpp ? c.heatmapSpp : c.spps[c.spps.size() / 2];
    if (std::find(c.spps.begin(), c.spps.end(), heatSpp) == c.spps.end())
        throw InputError(fmt::format("--heatmap-spp {} is not one of the --spp values", heatSpp));
    return heatSpp;
}

nlohmann::json referenceKey(const StudyConfig& c) {
    nlohmann::json key = {{"scene", sceneFingerprint(c.scene)},
                          {"width", c.width},
                          {"height", c.height},
                          {"spp", c.referenceSpp},
                          {"estimator", c.referenceEstimator},
                          {"sampler", c.referenceSampler},
                          {"max_depth", c.maxDepth},
                          {"seed", c.seed},
                          {"symmetric_n", c.options.symmetricN},
                          {"error", c.referenceError},
                          {"version", 2}};
    // Only a reference that splits names its splitting: the caches of references rendered before the option
    // existed (all unsplit) keep their key.
    if (c.referenceSplitting != "none") key["splitting"] = c.referenceSplitting;
    return key;
}

std::string referenceMethod(const StudyConfig& c) {
    return c.referenceSplitting == "none" ? c.referenceEstimator : c.referenceEstimator + "+" + c.referenceSplitting;
}

EstimatorOptions variantOptions(const StudyConfig& c, const StudyVariant& v) {
    EstimatorOptions o = c.options;
    o.symmetricMode = v.mode;
    if (v.orbit > 0) o.symmetricOrbit = v.orbit;
    return o;
}

RenderSettings studyRenderSettings(const StudyConfig& c) {
    RenderSettings rs;
    rs.width = c.width;
    rs.height = c.height;
    rs.threads = c.threads;
    rs.trace.maxDepth = c.maxDepth;
    return rs;
}

RenderSettings variantRenderSettings(const StudyConfig& c, const StudyVariant& v, std::uint32_t spp) {
    RenderSettings rs = studyRenderSettings(c);
    rs.spp = spp;
    rs.sampler = v.sampler;
    rs.trace.firstHitSplit = v.split;
    rs.trace.splitting = v.splitting;
    rs.trace.jointFirstBounce = c.jointFirstBounce && v.splitting == SplittingMode::None;
    return rs;
}

RenderSettings referenceRenderSettings(const StudyConfig& c, std::uint32_t spp) {
    RenderSettings rs = studyRenderSettings(c);
    rs.spp = spp;
    rs.sampler = c.referenceSampler;
    rs.trace.splitting = splittingMode(c.referenceSplitting);
    return rs;
}

std::uint32_t pilotSpp(SplittingMode splitting) { return learnsFactors(splitting) ? 2 * ears::kProbeMinSpp : 2; }

RenderSettings pilotRenderSettings(const StudyConfig& c, RenderSettings renders) {
    RenderSettings pilot = std::move(renders);
    pilot.spp = pilotSpp(pilot.trace.splitting);
    std::uint64_t samples = kPilotSamples;
    if (!c.spps.empty())
        samples = std::min(samples, static_cast<std::uint64_t>(c.width) * static_cast<std::uint64_t>(c.height) *
                                        *std::min_element(c.spps.begin(), c.spps.end()));
    const double pixels = static_cast<double>(samples) / pilot.spp;
    pilot.width = pilot.height = std::max(kPilotMinSide, static_cast<int>(std::ceil(std::sqrt(pixels))));
    pilot.seed = 99;
    return pilot;
}

RenderSettings pilotRenderSettings(const StudyConfig& c, const StudyVariant& v) {
    return pilotRenderSettings(c, variantRenderSettings(c, v, pilotSpp(v.splitting)));
}

}  // namespace symphong
