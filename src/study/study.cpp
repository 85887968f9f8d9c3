#include "study/study.h"

#include "accel/accel.h"
#include "io/files.h"
#include "io/image.h"
#include "io/input_error.h"
#include "render/progress.h"
#include "render/renderer.h"
#include "scene/scene.h"
#include "study/metrics.h"
#include "study/plot_script.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>

namespace fs = std::filesystem;

namespace symphong {

const char* const kStudyCsvHeader =
    "scene,estimator,variant,sampler,mode,spp,repeat,width,height,seconds,rays,samples,mean_luminance,mean_luminance_std_error,"
    "relative_bias,mse_raw,mse,rmse,relmse,efficiency,efficiency_relmse,pixel_variance_within,group_relative_bias,"
    "group_bias_std_error,group_bias_z,group_bias_threshold,group_bias_significant,group_pixel_variance,split,"
    "group_first_bounce_variance";

std::string studyCsv(const std::vector<StudyRow>& rows) {
    std::string out = std::string(kStudyCsvHeader) + "\n";
    for (const StudyRow& r : rows)
        out += fmt::format("{},{},{},{},{},{},{},{},{},{:.6g},{},{},{:.9g},{:.6g},{:.6g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.6g},{:.6g},{:.6g},{:.4g},{:.4g},{},{:.6g},{},{:.6g}\n",
                           r.scene, r.estimator, r.variant, r.sampler, r.mode, r.spp, r.repeat, r.width, r.height, r.seconds, r.rays, r.samples, r.meanLuminance,
                           r.meanStdError, r.relativeBias, r.mseRaw, r.mse, r.rmse, r.relMse, r.efficiency, r.efficiencyRel, r.pixelVarianceWithin,
                           r.groupRelativeBias, r.groupBiasStdError, r.groupBiasZ, r.groupBiasThreshold, r.groupBiasSignificant ? 1 : 0,
                           r.groupPixelVariance, r.split, r.groupFirstBounceVariance);
    return out;
}

std::vector<StudySummary> summarizeStudy(const std::vector<StudyRow>& rows) {
    std::vector<StudySummary> out;
    std::map<std::pair<std::string, std::uint32_t>, std::vector<const StudyRow*>> groups;
    for (const StudyRow& r : rows) {
        auto& g = groups[{r.variant, r.spp}];
        if (g.empty()) {
            StudySummary s;
            s.estimator = r.estimator;
            s.variant = r.variant;
            s.sampler = r.sampler;
            s.mode = r.mode;
            s.spp = r.spp;
            out.push_back(s);
        }
        g.push_back(&r);
    }
    for (StudySummary& s : out) {
        const auto& g = groups[{s.variant, s.spp}];
        const double n = static_cast<double>(g.size());
        std::vector<double> eff, effRel, rmse, mse, relMse;
        double meanRmse = 0;
        for (const StudyRow* r : g) {
            s.seconds += r->seconds / n;
            meanRmse += r->rmse / n;
            s.rays += static_cast<double>(r->rays) / n;
            eff.push_back(r->efficiency);
            effRel.push_back(r->efficiencyRel);
            rmse.push_back(r->rmse);
            mse.push_back(r->mse);
            relMse.push_back(r->relMse);
        }
        double spread = 0;
        for (const StudyRow* r : g) spread += (r->rmse - meanRmse) * (r->rmse - meanRmse);
        s.rmseSpread = g.size() > 1 ? std::sqrt(spread / (n - 1) / n) : 0.0;  // standard error of the mean RMSE
        const auto median = [](std::vector<double> v) {
            std::sort(v.begin(), v.end());
            return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
        };
        s.rmse = median(rmse);
        s.mse = median(mse);
        s.relMse = median(relMse);
        s.efficiency = median(eff);
        s.efficiencyRel = median(effRel);
        s.firstBounceVariance = g.front()->groupFirstBounceVariance;
        s.relativeBias = g.front()->groupRelativeBias;
        s.biasStdError = g.front()->groupBiasStdError;
        s.biasZ = g.front()->groupBiasZ;
        s.biasSignificant = g.front()->groupBiasSignificant;
        s.pixelVariance = g.front()->groupPixelVariance;
    }
    return out;
}

std::vector<StudyVariant> studyVariants(const StudyConfig& c) {
    std::vector<StudyVariant> out;
    for (const std::string& e : c.estimators) {
        const auto probe = makeEstimator(e, c.options);
        const bool set = hasSymmetricModes(e);
        std::vector<int> splits{1};
        if (std::find(c.splitEstimators.begin(), c.splitEstimators.end(), e) != c.splitEstimators.end())
            for (int k : c.splits)
                if (k > 1) splits.push_back(k);
        for (SymmetricMode mode : set ? c.modes : std::vector<SymmetricMode>{SymmetricMode::Branch})
            for (int split : splits) {
                // A branch-mode set already traces many directions from its first hit: not split further.
                EstimatorOptions o = c.options;
                o.symmetricMode = mode;
                if (split > 1 && makeEstimator(e, o)->returnsSets()) continue;
                for (const std::string& sampler : c.samplers) {
                    StudyVariant v;
                    v.estimator = e;
                    v.mode = mode;
                    v.split = split;
                    v.sampler = effectiveSampler(*probe, sampler);
                    v.label = e + (set && mode == SymmetricMode::Spread ? "+spread" : "") + (split > 1 ? fmt::format("+split{}", split) : "");
                    if (c.samplers.size() > 1 && probe->requiredSampler().empty()) v.label += "@" + v.sampler;
                    if (std::none_of(out.begin(), out.end(), [&](const StudyVariant& o) { return o.label == v.label; })) out.push_back(v);
                }
            }
    }
    return out;
}

namespace {

/// The summary of `estimator` (branch mode) under the same sampler as `like`, at the same spp.
const StudySummary* sameSampler(const std::vector<StudySummary>& s, const std::string& estimator, const StudySummary& like) {
    for (const auto& x : s)
        if (x.estimator == estimator && x.mode == "branch" && x.spp == like.spp && (x.sampler == like.sampler || estimator == "stratified"))
            return &x;
    return nullptr;
}

std::string factor(double x) { return x >= 10 ? fmt::format("{:.0f}x", x) : fmt::format("{:.2g}x", x); }

bool biasedAnywhere(const std::vector<StudySummary>& s, const std::string& variant) {
    for (const auto& x : s)
        if (x.variant == variant && x.biasSignificant) return true;
    return false;
}

}  // namespace

std::string studyConclusion(const std::vector<StudySummary>& summary, const std::vector<std::uint32_t>& spps) {
    if (summary.empty()) return "No results.";
    std::uint32_t top = 0;
    for (const auto& s : summary) top = std::max(top, s.spp);
    std::vector<const StudySummary*> atTop;
    for (const auto& s : summary)
        if (s.spp == top) atTop.push_back(&s);
    std::string text;
    for (const char* key : {"MSE", "relMSE"}) {
        const bool rel = std::string(key) == "relMSE";
        const auto eff = [rel](const StudySummary& s) { return rel ? s.efficiencyRel : s.efficiency; };
        const StudySummary* best = nullptr;
        for (const auto* s : atTop)
            if (!biasedAnywhere(summary, s->variant) && (!best || eff(*s) > eff(*best))) best = s;
        if (!best) continue;
        text += fmt::format("By {} at {} spp the most efficient unbiased variant is `{}`", key, top, best->variant);
        std::vector<std::string> parts;
        for (const auto* s : atTop)
            if (s != best && !biasedAnywhere(summary, s->variant) && eff(*s) > 0)
                parts.push_back(fmt::format("{} that of `{}`", factor(eff(*best) / eff(*s)), s->variant));
        if (!parts.empty()) text += fmt::format(" (its efficiency is {})", fmt::join(parts, ", "));
        text += ". ";
    }
    // The symmetric variants against cosine and phong under the same sampler.
    for (const auto* s : atTop) {
        if (s->estimator != "symmetric" && s->estimator != "symmetric-shifted") continue;
        std::vector<std::string> parts;
        for (const char* other : {"cosine", "stratified", "phong"})
            if (const StudySummary* o = sameSampler(summary, other, *s); o && o->efficiency > 0 && o->efficiencyRel > 0)
                parts.push_back(fmt::format("{} `{}`'s by MSE ({} by relMSE)", factor(s->efficiency / o->efficiency), o->variant,
                                            factor(s->efficiencyRel / o->efficiencyRel)));
        if (!parts.empty()) text += fmt::format("`{}` reaches {}. ", s->variant, fmt::join(parts, ", "));
    }
    // Each estimator's samplers against each other.
    std::vector<std::string> samplerParts;
    for (const auto* s : atTop)
        if (s->sampler != "independent")
            for (const auto* o : atTop)
                if (o->estimator == s->estimator && o->mode == s->mode && o->sampler == "independent" && s->mse > 0)
                    samplerParts.push_back(fmt::format("`{}` {} lower MSE than `{}` ({} the efficiency)", s->variant, factor(o->mse / s->mse),
                                                       o->variant, factor(s->efficiency / o->efficiency)));
    if (!samplerParts.empty()) text += fmt::format("Samplers at {} spp: {}. ", top, fmt::join(samplerParts, "; "));
    std::vector<std::string> winners;
    for (std::uint32_t spp : spps) {
        const StudySummary* w = nullptr;
        for (const auto& s : summary)
            if (s.spp == spp && !biasedAnywhere(summary, s.variant) && (!w || s.rmse < w->rmse)) w = &s;
        if (w) winners.push_back(fmt::format("{} spp: `{}`", spp, w->variant));
    }
    if (!winners.empty())
        text += fmt::format("At equal samples per pixel, the lowest RMSE among unbiased variants goes to {} (branch-mode symmetric "
                            "estimators trace 16 to 24 paths per camera sample, so equal samples is not equal work). ",
                            fmt::join(winners, ", "));
    std::vector<std::string> biased;
    for (const auto* s : atTop)
        if (s->biasSignificant)
            biased.push_back(fmt::format("`{}` ({:+.1f}% +- {:.1f}%, z = {:.0f})", s->variant, 100 * s->relativeBias,
                                         100 * s->biasStdError, s->biasZ));
    if (!biased.empty())
        text += fmt::format("Significantly biased against the reference (|z| > 4): {}; their error stops falling with more "
                            "samples, so their efficiency means little.",
                            fmt::join(biased, ", "));
    else
        text += "No variant is significantly biased (|z| > 4) against the reference.";
    return text;
}

namespace {

std::string sceneFingerprint(const std::string& spec) {
    if (spec == "cornell" || !fs::exists(spec)) return spec;
    const std::string text = readTextFile(spec);
    return fmt::format("{}:{:016x}", spec, std::hash<std::string>{}(text));
}

std::string findPython(const std::string& preferred) {
    std::vector<std::string> candidates;
    if (!preferred.empty()) candidates.push_back(preferred);
    candidates.push_back("/usr/bin/python3");
    candidates.push_back("python3");
    for (const std::string& py : candidates) {
        const std::string cmd = fmt::format("'{}' -c 'import matplotlib' >/dev/null 2>&1", py);
        if (std::system(cmd.c_str()) == 0) return py;
    }
    return {};
}

nlohmann::json rowJson(const StudyRow& r) {
    return {{"scene", r.scene}, {"estimator", r.estimator}, {"variant", r.variant}, {"sampler", r.sampler}, {"mode", r.mode}, {"spp", r.spp}, {"repeat", r.repeat}, {"width", r.width},
            {"height", r.height}, {"seconds", r.seconds}, {"rays", r.rays}, {"samples", r.samples},
            {"mean_luminance", r.meanLuminance}, {"mean_luminance_std_error", r.meanStdError}, {"relative_bias", r.relativeBias},
            {"mse_raw", r.mseRaw}, {"mse", r.mse}, {"rmse", r.rmse}, {"relmse", r.relMse}, {"efficiency", r.efficiency}, {"efficiency_relmse", r.efficiencyRel},
            {"pixel_variance_within", r.pixelVarianceWithin}, {"group_relative_bias", r.groupRelativeBias},
            {"group_bias_std_error", r.groupBiasStdError}, {"group_bias_z", r.groupBiasZ}, {"group_bias_threshold", r.groupBiasThreshold},
            {"group_bias_significant", r.groupBiasSignificant}, {"group_pixel_variance", r.groupPixelVariance}, {"split", r.split},
            {"group_first_bounce_variance", r.groupFirstBounceVariance}};
}

nlohmann::json summaryJson(const StudySummary& s) {
    return {{"estimator", s.estimator}, {"variant", s.variant}, {"sampler", s.sampler}, {"mode", s.mode}, {"spp", s.spp}, {"seconds", s.seconds}, {"rays", s.rays}, {"rmse", s.rmse},
            {"rmse_spread", s.rmseSpread}, {"mse", s.mse}, {"relmse", s.relMse}, {"efficiency", s.efficiency},
            {"efficiency_relmse", s.efficiencyRel},
            {"relative_bias", s.relativeBias}, {"bias_std_error", s.biasStdError}, {"bias_z", s.biasZ},
            {"bias_significant", s.biasSignificant}, {"pixel_variance", s.pixelVariance},
            {"first_bounce_variance", s.firstBounceVariance}, {"first_bounce_share", s.firstBounceShare()}};
}

struct Crop {
    int x, y, w, h;
};

std::string modeList(const std::vector<SymmetricMode>& modes) {
    std::vector<std::string> names;
    for (SymmetricMode m : modes) names.emplace_back(symmetricModeName(m));
    return fmt::format("{}", fmt::join(names, ","));
}

std::string reportMarkdown(const StudyConfig& c, const std::string& sceneName, const std::vector<StudySummary>& summary,
                           const std::string& conclusion, const std::string& referenceNote, double referenceNoise, bool plotted,
                           std::uint32_t heatSpp, bool cancelled, int processes) {
    std::string md = fmt::format("# Estimator study: {}\n\n", sceneName);
    if (cancelled) md += "**Interrupted**: these are the rows finished before the study was stopped.\n\n";
    md += fmt::format(
        "Scene `{}`, {}x{} pixels, max depth {}, {} independent repeat(s) per variant and sample count, seed {}. {}\n"
        "A variant is an estimator under a sampler (`@sampler`), in spread mode for the set estimators (`+spread`), with "
        "K directions from each camera sample's first hit (`+splitK`).\n"
        "Command: `symphong study {} --estimators {} --samplers {} --symmetric-modes {} --spp {} --repeats {} --width {} --height {}{}{}{}`.\n\n",
        c.scene, c.width, c.height, c.maxDepth, c.repeats, c.seed, referenceNote, c.scene, fmt::join(c.estimators, ","),
        fmt::join(c.samplers, ","), modeList(c.modes), fmt::join(c.spps, ","), c.repeats, c.width, c.height,
        c.splits.empty() ? "" : fmt::format(" --splits {} --split-estimators {}", fmt::join(c.splits, ","), fmt::join(c.splitEstimators, ",")),
        std::string(c.budgetPairs > 0 ? fmt::format(" --budget-pairs {}", c.budgetPairs) : "") + (c.jointFirstBounce ? " --joint-first-bounce" : ""),
        c.options.symmetricOrbit != EstimatorOptions{}.symmetricOrbit ? fmt::format(" --symmetric-orbit {}", c.options.symmetricOrbit) : "");
    if (processes > 1) md += fmt::format("Each render was shared among {} processes (MPI ranks); times are the whole job's.\n\n", processes);
    md += "## Conclusion\n\n" + conclusion + "\n\n";
    for (const auto& s : summary)
        if (s.mse > 0 && referenceNoise > 0.5 * s.mse) {
            md += fmt::format("**Warning:** the reference's own noise ({:.3g}) is at least half of some estimators' squared error "
                              "(`{}` at {} spp: {:.3g}); their RMSE and efficiency are uncertain. Raise --reference-spp.\n\n",
                              referenceNoise, s.variant, s.spp, s.mse);
            break;
        }
    if (plotted) {
        md += "## Convergence\n\n![RMSE against samples per pixel](convergence_spp.png)\n\n"
              "![RMSE against render time](convergence_time.png)\n\n"
              "## Efficiency\n\n![Efficiency relative to cosine](efficiency.png)\n\n";
        md += fmt::format("## Where the error is ({} spp)\n\n![Per-pixel relative error](heatmaps.png)\n\n![Crops](crops.png)\n\n", heatSpp);
    } else {
        md += "Plots were not made (no python3 with matplotlib); run `python3 scripts/plot_study.py` on this folder.\n\n";
    }
    // The variance budget: where the remaining variance comes from.
    std::string budget;
    for (const auto& s : summary)
        if (s.firstBounceShare() >= 0)
            budget += fmt::format("| {} | {} | {:.3g} | {:.3g} | {:.0f}% |\n", s.variant, s.spp, s.pixelVariance, s.firstBounceVariance,
                                  100 * s.firstBounceShare());
    if (!budget.empty())
        md += fmt::format("## Variance budget ({} pairs)\n\nMean pixel variance (luminance) across the repeats, and the part of it that "
                          "comes from the first-bounce directions: the mean of (Y_1 - Y_2)^2 / 2 over pairs of renders that differ only in "
                          "the first hit's estimator numbers (`--first-bounce-stream` 1 and 2), every other decision of the path keeping "
                          "its numbers. The rest comes from the pixel position, light sampling and the deeper bounces (law of total "
                          "variance). With few repeats each figure is uncertain by tens of percent.\n\n"
                          "| variant | spp | pixel variance | from the first bounce | share |\n|---|---:|---:|---:|---:|\n{}\n",
                          c.budgetPairs, budget);
    md += "## Equal samples\n\nMedians over the repeats; RMSE of luminance against the reference (its own noise removed), "
          "relMSE = mean of (Y - Y_ref)^2 / (Y_ref^2 + 0.01), bias of the mean image with its standard error (flagged when "
          "|z| > 4), efficiency 1/(MSE x time), each the median over repeats (time: the mean), relative to `cosine` under the same sampler at the "
          "same spp.\n\nThe last column is the same with relMSE in place of MSE.\n\n"
          "| variant | spp | time (s) | Mrays | RMSE | relMSE | pixel variance | rel. bias | efficiency vs cosine | relMSE efficiency vs cosine |\n"
          "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    for (const auto& s : summary) {
        const StudySummary* cos = sameSampler(summary, "cosine", s);
        md += fmt::format("| {} | {} | {:.3g} | {:.3g} | {:.4g} | {:.4g} | {:.3g} | {:+.2f}% +- {:.2f}%{} | {} | {} |\n", s.variant,
                          s.spp, s.seconds, s.rays / 1e6, s.rmse, s.relMse, s.pixelVariance, 100 * s.relativeBias, 100 * s.biasStdError,
                          s.biasSignificant ? " **biased**" : "", cos && cos->efficiency > 0 ? factor(s.efficiency / cos->efficiency) : "-",
                          cos && cos->efficiencyRel > 0 ? factor(s.efficiencyRel / cos->efficiencyRel) : "-");
    }
    // Equal time: efficiency is about constant in spp for an unbiased estimator, so the MSE reachable in
    // time T is about 1/(efficiency x T); T = cosine's time at the highest spp.
    std::uint32_t top = 0;
    for (const auto& s : summary) top = std::max(top, s.spp);
    const StudySummary* ref = nullptr;
    for (const auto& s : summary)
        if (s.spp == top && s.estimator == "cosine" && (!ref || s.sampler == "independent")) ref = &s;
    if (!ref && !summary.empty()) ref = &summary.front();
    if (ref && ref->seconds > 0) {
        const double T = ref->seconds;
        md += fmt::format("\n## Equal time\n\nRMSE each estimator would reach in {:.3g} s (the time `{}` took at {} spp), from its "
                          "efficiency at the sample count whose time is closest: RMSE_T = sqrt(1/(efficiency x T)).\n\n"
                          "| estimator | from spp | RMSE at {:.3g} s | vs `{}` |\n|---|---:|---:|---:|\n",
                          T, ref->variant, top, T, ref->variant);
        const double refRmse = std::sqrt(1.0 / (ref->efficiency * T));
        for (const StudyVariant& v : studyVariants(c)) {
            const std::string& est = v.label;
            const StudySummary* bestFit = nullptr;
            for (const auto& s : summary)
                if (s.variant == est && s.seconds > 0 && s.efficiency > 0 &&
                    (!bestFit || std::abs(std::log(s.seconds / T)) < std::abs(std::log(bestFit->seconds / T))))
                    bestFit = &s;
            if (!bestFit) continue;
            const double rmseT = std::sqrt(1.0 / (bestFit->efficiency * T));
            md += fmt::format("| {}{} | {} | {:.4g} | {:.2f}x |\n", est, biasedAnywhere(summary, est) ? " (biased)" : "", bestFit->spp, rmseT,
                              rmseT / refRmse);
        }
    }
    md += "\nFiles: `results.csv` and `results.json` (one row per estimator x spp x repeat), `reference.exr` (+ `reference.json`), "
          "`renders/`, `heatmaps/`.\n";
    return md;
}

}  // namespace

namespace {

std::function<void(std::size_t)>& rowObserver() {
    static std::function<void(std::size_t)> observer;
    return observer;
}

}  // namespace

void setStudyRowObserver(std::function<void(std::size_t rows)> observer) { rowObserver() = std::move(observer); }

namespace {

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
    if (c.referenceEstimator == "paper") throw InputError("--reference-estimator: 'paper' is biased; choose an unbiased estimator");
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

/// The study's reference image with what is known of it.
struct Reference {
    Image image;
    MeanWithError mean;
    double noise = 0;  ///< mean over pixels of its variance-of-mean (luminance); 0 when unknown
    std::string note;  ///< the report's sentence on where it came from
    bool have = false;  ///< false: it must be rendered
};

/// The given reference (--reference), or the one cached in `dir` for the same settings (`key`);
/// `have` false when there is none (a damaged cache counts as none).
Reference existingReference(const StudyConfig& c, const fs::path& dir, const nlohmann::json& key) {
    Reference ref;
    const fs::path exr = dir / "reference.exr", json = dir / "reference.json";
    if (!c.referencePath.empty()) {
        ref.image = readExr(c.referencePath);
        if (ref.image.width != c.width || ref.image.height != c.height)
            throw InputError(fmt::format("--reference {}: {}x{} does not match the study's {}x{}", c.referencePath, ref.image.width,
                                         ref.image.height, c.width, c.height));
        ref.mean = meanLuminance(ref.image);
        ref.note = fmt::format("Reference: `{}` (given; its own noise is unknown and taken as zero).", c.referencePath);
        ref.have = true;
    } else if (fs::exists(exr) && fs::exists(json)) {
        try {
            const auto cached = nlohmann::json::parse(readTextFile(json.string()));
            if (cached.value("key", nlohmann::json()) == key) {
                ref.image = readExr(exr.string());
                ref.mean = {cached.at("mean_luminance").get<double>(), cached.at("mean_std_error").get<double>()};
                ref.noise = cached.at("pixel_variance").get<double>();
                ref.have = ref.image.width == c.width && ref.image.height == c.height;
                ref.note = fmt::format("Reference: `{}` at {} spp, cached in reference.exr.", c.referenceEstimator, c.referenceSpp);
            }
        } catch (const std::exception&) {
            ref = Reference{};  // a damaged cache is re-rendered
        }
    }
    return ref;
}

}  // namespace

RenderResult StudyRuntime::render(const Scene& scene, const Accel& accel, const Estimator& estimator, const RenderSettings& settings,
                                  std::atomic<std::uint64_t>* progress) const {
    return symphong::render(scene, accel, estimator, settings, progress);
}

StudyOutcome runStudy(const StudyConfig& config, const std::atomic<bool>* cancel, bool showProgress, const StudyRuntime* runtime) {
    const StudyRuntime inThisProcess;
    const StudyRuntime& rt = runtime ? *runtime : inThisProcess;
    const bool writer = rt.writer();
    StudyConfig c = config;
    const fs::path dir(c.outDir);
    std::uint32_t heatSpp = 0;
    std::vector<StudyVariant> variants;
    Scene scene;
    nlohmann::json refKey;
    Reference ref;
    // Preparing: every process checks the configuration and loads the scene; the writer also makes the
    // output directory and looks for a reference. Bad input in any process stops all of them with one
    // message (the process that met it keeps its exception's type).
    std::exception_ptr failure;
    std::string error;
    try {
        heatSpp = checkConfig(c);
        variants = studyVariants(c);
        scene = loadScene(c.scene);
        refKey = {{"scene", sceneFingerprint(c.scene)}, {"width", c.width}, {"height", c.height}, {"spp", c.referenceSpp},
                  {"estimator", c.referenceEstimator}, {"sampler", c.referenceSampler}, {"max_depth", c.maxDepth}, {"seed", c.seed},
                  {"symmetric_n", c.options.symmetricN}, {"version", 1}};
        if (writer) {
            for (const std::string& w : scene.warnings) fmt::print(stderr, "symphong: warning: {}\n", w);
            std::error_code ec;
            fs::create_directories(dir / "renders", ec);
            fs::create_directories(dir / "heatmaps", ec);
            if (ec || !fs::is_directory(dir)) throw InputError(fmt::format("--out {}: cannot create the directory", c.outDir));
            writeFile((dir / "results.csv").string(), std::string(kStudyCsvHeader) + "\n");  // fails early if unwritable
            ref = existingReference(c, dir, refKey);
        }
    } catch (const InputError& e) {
        failure = std::current_exception();
        error = e.what();
    }
    if (const std::string agreed = rt.agreeOnError(error); !agreed.empty()) {
        if (failure && agreed == error) std::rethrow_exception(failure);
        throw InputError(agreed);
    }
    ref.have = rt.writersValue(ref.have);

    const Accel accel(scene);
    RenderSettings base;
    base.width = c.width;
    base.height = c.height;
    base.threads = c.threads;
    base.trace.maxDepth = c.maxDepth;
    base.cancel = cancel;

    // Cost per camera sample of each estimator, from a small pilot render, so the progress bar's ETA
    // accounts for estimators that trace 24 paths per sample.
    const auto variantOptions = [&](const StudyVariant& v) {
        EstimatorOptions o = c.options;
        o.symmetricMode = v.mode;
        return o;
    };
    const auto pilotCost = [&](const std::string& name, const EstimatorOptions& options, const std::string& sampler) {
        RenderSettings pilot = base;
        pilot.width = pilot.height = 24;
        pilot.spp = 2;
        pilot.seed = 99;
        pilot.sampler = sampler;
        pilot.cancel = nullptr;
        const auto est = makeEstimator(name, options);
        const RenderResult r = render(scene, accel, *est, pilot);
        return std::max(1e-9, r.stats.seconds / static_cast<double>(r.stats.samples));
    };
    // Only the writer shows progress; the other processes skip the pilots.
    std::map<std::string, double> cost;
    double total = 0;
    if (writer)
        for (const auto& v : variants) {
            cost[v.label] = pilotCost(v.estimator, variantOptions(v), v.sampler);
            for (auto s : c.spps) total += cost[v.label] * s * c.width * c.height * c.repeats;
        }
    std::atomic<std::uint64_t> rowSamples{0};
    double doneBefore = 0, currentCost = 0;
    std::string currentLabel = "reference";
    std::mutex labelMutex;
    const double refCost = ref.have || !writer ? 0.0 : pilotCost(c.referenceEstimator, c.options, c.referenceSampler);
    const double refWork = refCost * c.referenceSpp * c.width * c.height;
    total += refWork;

    int rowIndex = 0;
    const int rowCount = static_cast<int>(variants.size() * c.spps.size()) * c.repeats;
    ProgressBar bar([&] { return doneBefore + currentCost * static_cast<double>(rowSamples.load(std::memory_order_relaxed)); }, total,
                    [&] {
                        std::lock_guard<std::mutex> lock(labelMutex);
                        return currentLabel;
                    },
                    showProgress);

    StudyOutcome outcome;
    if (!ref.have) {
        currentCost = refCost;
        RenderSettings rs = base;
        rs.spp = c.referenceSpp;
        rs.seed = mixSeed(c.seed, 0xFEFE);
        rs.sampler = c.referenceSampler;
        const auto est = makeEstimator(c.referenceEstimator, c.options);
        const RenderResult r = rt.render(scene, accel, *est, rs, &rowSamples);
        if (r.cancelled) {
            bar.finish();
            outcome.cancelled = true;
            return outcome;
        }
        outcome.referenceRendered = true;
        if (writer) {
            // Used as the cache stores it (32-bit float), so a study gives the same numbers, bit for bit,
            // whether its reference was just rendered or read back from reference.exr.
            ref.image = r.image;
            for (Color& p : ref.image.pixels)
                for (int ch = 0; ch < 3; ++ch) p[ch] = static_cast<float>(p[ch]);
            ref.mean = meanLuminance(ref.image, &r.variance);
            for (const Color& v : r.variance.pixels) ref.noise += luminanceVariance(v) / static_cast<double>(r.variance.pixels.size());
            writeExr(ref.image, (dir / "reference.exr").string(), false);
            writeFile((dir / "reference.json").string(),
                      nlohmann::json{{"key", refKey}, {"mean_luminance", ref.mean.mean}, {"mean_std_error", ref.mean.stdError},
                                     {"pixel_variance", ref.noise}, {"seconds", r.stats.seconds}}
                              .dump(2) +
                          "\n");
            ref.note = fmt::format("Reference: `{}` at {} spp ({:.1f} s), cached in reference.exr.", c.referenceEstimator, c.referenceSpp,
                                   r.stats.seconds);
        }
    }
    doneBefore += refWork;
    rowSamples = 0;
    if (writer) writePng(ref.image, (dir / "reference.png").string());

    const Crop crop{c.width / 3, c.height / 3, std::max(1, c.width / 3), std::max(1, c.height / 3)};
    const auto writeResults = [&] {
        writeFile((dir / "results.csv").string(), studyCsv(outcome.rows));
        nlohmann::json j;
        nlohmann::json variantList = nlohmann::json::array();
        for (const auto& v : variants)
            variantList.push_back({{"label", v.label}, {"estimator", v.estimator}, {"sampler", v.sampler}, {"mode", symmetricModeName(v.mode)},
                                   {"split", v.split}});
        j["config"] = {{"scene", scene.name}, {"scene_spec", c.scene}, {"estimators", c.estimators}, {"samplers", c.samplers},
                       {"variants", variantList}, {"spp", c.spps}, {"symmetric_orbit", c.options.symmetricOrbit},
                       {"budget_pairs", c.budgetPairs}, {"joint_first_bounce", c.jointFirstBounce},
                       {"repeats", c.repeats}, {"width", c.width}, {"height", c.height}, {"max_depth", c.maxDepth}, {"seed", c.seed},
                       {"processes", rt.processes()},
                       {"reference", {{"path", c.referencePath}, {"estimator", c.referenceEstimator}, {"spp", c.referenceSpp},
                                      {"mean_luminance", ref.mean.mean}, {"pixel_variance", ref.noise}}},
                       {"heatmap", {{"spp", heatSpp}, {"width", c.width}, {"height", c.height}, {"crop", {crop.x, crop.y, crop.w, crop.h}}}}};
        j["rows"] = nlohmann::json::array();
        for (const auto& r : outcome.rows) j["rows"].push_back(rowJson(r));
        outcome.summary = summarizeStudy(outcome.rows);
        j["summary"] = nlohmann::json::array();
        for (const auto& s : outcome.summary) j["summary"].push_back(summaryJson(s));
        outcome.conclusion = studyConclusion(outcome.summary, c.spps);
        j["conclusion"] = outcome.conclusion;
        writeFile((dir / "results.json").string(), j.dump(1) + "\n");
    };

    for (std::uint32_t spp : c.spps) {
        for (std::size_t ei = 0; ei < variants.size() && !outcome.cancelled; ++ei) {
            const StudyVariant& variant = variants[ei];
            const std::string& name = variant.label;
            const auto est = makeEstimator(variant.estimator, variantOptions(variant));
            std::vector<Image> images;
            std::vector<MeanWithError> means;
            const std::size_t firstRow = outcome.rows.size();
            for (int rep = 0; rep < c.repeats; ++rep) {
                {
                    std::lock_guard<std::mutex> lock(labelMutex);
                    currentLabel = fmt::format("{} {} spp, repeat {}/{} (row {}/{})", name, spp, rep + 1, c.repeats, rowIndex + 1, rowCount);
                }
                currentCost = cost[name];
                rowSamples = 0;
                RenderSettings rs = base;
                rs.spp = spp;
                rs.sampler = variant.sampler;
                rs.trace.firstHitSplit = variant.split;
                    rs.trace.jointFirstBounce = c.jointFirstBounce;
                rs.seed = mixSeed(mixSeed(mixSeed(c.seed, ei + 1), spp), static_cast<std::uint64_t>(rep));
                const RenderResult r = rt.render(scene, accel, *est, rs, &rowSamples);
                doneBefore += cost[name] * spp * c.width * c.height;
                rowSamples = 0;
                ++rowIndex;
                if (r.cancelled) {
                    outcome.cancelled = true;
                    break;
                }
                if (!writer) continue;  // it helped render; the writer measures
                StudyRow row;
                row.scene = scene.name;
                row.estimator = variant.estimator;
                row.variant = variant.label;
                row.sampler = variant.sampler;
                row.mode = std::string(symmetricModeName(variant.mode));
                row.spp = spp;
                row.split = variant.split;
                row.repeat = rep;
                row.width = c.width;
                row.height = c.height;
                row.seconds = r.stats.seconds;
                row.rays = r.stats.rays;
                row.samples = r.stats.samples;
                const MeanWithError m = meanLuminance(r.image, &r.variance);
                row.meanLuminance = m.mean;
                row.meanStdError = m.stdError;
                row.relativeBias = ref.mean.mean != 0 ? (m.mean - ref.mean.mean) / ref.mean.mean : 0.0;
                const ImageError err = imageError(r.image, ref.image);
                row.mseRaw = err.mse;
                // Remove the reference's own noise from the error; where that would leave less than 5% of
                // the raw error the reference is too noisy to say more (the report warns).
                row.mse = std::max(err.mse - ref.noise, 0.05 * err.mse);
                row.rmse = std::sqrt(row.mse);
                row.relMse = err.relMse;
                row.efficiency = 1.0 / (row.mse * std::max(row.seconds, 1e-9));
                row.efficiencyRel = row.relMse > 0 ? 1.0 / (row.relMse * std::max(row.seconds, 1e-9)) : 0.0;
                for (const Color& v : r.variance.pixels)
                    row.pixelVarianceWithin += luminanceVariance(v) / static_cast<double>(r.variance.pixels.size());
                means.push_back(m);
                if (spp == heatSpp && rep == 0) {
                    writePng(r.image, (dir / "renders" / (name + ".png")).string());
                    const std::vector<float> map = relativeErrorMap(r.image, ref.image);
                    writeFile((dir / "heatmaps" / (name + ".f32")).string(),
                              std::string(reinterpret_cast<const char*>(map.data()), map.size() * sizeof(float)));
                }
                images.push_back(r.image);
                outcome.rows.push_back(row);
                if (rowObserver()) rowObserver()(outcome.rows.size());
            }
            if (outcome.cancelled) {
                outcome.rows.resize(firstRow);  // keep only whole groups: their group columns are complete
                break;
            }
            // The variance budget at the top spp: pairs of renders that differ only in the first bounce's numbers.
            double firstBounce = -1;
            if (spp == c.spps.back() && c.budgetPairs > 0) {
                double sum = 0;
                for (int b = 0; b < c.budgetPairs && !outcome.cancelled; ++b) {
                    RenderSettings rs = base;
                    rs.spp = spp;
                    rs.sampler = variant.sampler;
                    rs.trace.firstHitSplit = variant.split;
                    rs.trace.jointFirstBounce = c.jointFirstBounce;
                    rs.seed = mixSeed(mixSeed(mixSeed(c.seed, ei + 1), 0xB0D6E7), static_cast<std::uint64_t>(b));
                    Image pair[2];
                    for (std::uint32_t stream = 1; stream <= 2 && !outcome.cancelled; ++stream) {
                        {
                            std::lock_guard<std::mutex> lock(labelMutex);
                            currentLabel = fmt::format("{} {} spp, variance budget {}/{}", name, spp, b + 1, c.budgetPairs);
                        }
                        rs.trace.firstBounceStream = stream;
                        const RenderResult r = rt.render(scene, accel, *est, rs, &rowSamples);
                        doneBefore += cost[name] * spp * c.width * c.height;
                        rowSamples = 0;
                        outcome.cancelled = r.cancelled;
                        pair[stream - 1] = r.image;
                    }
                    if (!outcome.cancelled && writer) sum += halfSquaredDifference(pair[0], pair[1]);
                }
                firstBounce = sum / c.budgetPairs;
            }
            if (outcome.cancelled) {
                outcome.rows.resize(firstRow);
                break;
            }
            if (!writer) continue;
            const BiasEstimate bias = relativeBias(means, ref.mean);
            std::vector<const Image*> ptrs;
            for (const Image& im : images) ptrs.push_back(&im);
            const double pv = pixelVarianceAcrossRepeats(ptrs);
            for (std::size_t i = firstRow; i < outcome.rows.size(); ++i) {
                StudyRow& row = outcome.rows[i];
                row.groupRelativeBias = bias.relative;
                row.groupBiasStdError = bias.stdError;
                row.groupBiasZ = bias.z;
                row.groupBiasThreshold = bias.threshold;
                row.groupBiasSignificant = bias.significant;
                row.groupPixelVariance = pv;
                row.groupFirstBounceVariance = firstBounce;
            }
            if (writer) writeResults();
        }
        if (outcome.cancelled) break;
    }
    bar.finish();
    if (!writer) return outcome;
    writeResults();

    if (!outcome.cancelled && c.plots) {
        const std::string py = findPython(c.python);
        if (py.empty()) {
            fmt::print(stderr, "symphong: warning: no python3 with matplotlib found (Debian: apt-get install python3-matplotlib); "
                               "no plots were made\n");
        } else {
            const std::string script = (dir / "plot_study.py").string();
            writeFile(script, kPlotStudyScript);
            const std::string cmd = fmt::format("'{}' '{}' '{}'", py, script, dir.string());
            outcome.plotted = std::system(cmd.c_str()) == 0;
            if (!outcome.plotted) fmt::print(stderr, "symphong: warning: the plotting script failed: {}\n", cmd);
        }
    }
    writeFile((dir / "report.md").string(),
                  reportMarkdown(c, scene.name, outcome.summary, outcome.conclusion, ref.note, ref.noise, outcome.plotted, heatSpp,
                                 outcome.cancelled, rt.processes()));
    return outcome;
}

}  // namespace symphong
