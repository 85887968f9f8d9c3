// The study's numbers: rows as CSV and JSON, the summary of each (variant, spp) group, and the
// conclusion computed from them (which variant wins where, by the estimators' traits, never their names).
#include "estimators/registry.h"
#include "sampling/sampler_registry.h"
#include "study/answer.h"
#include "study/study_parts.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>

namespace symphong {

const char* const kStudyCsvHeader =
    "scene,estimator,variant,sampler,mode,spp,repeat,width,height,seconds,rays,samples,mean_luminance,mean_luminance_std_error,"
    "relative_bias,mse_raw,mse,rmse,relmse,efficiency,efficiency_relmse,pixel_variance_within,group_relative_bias,"
    "group_bias_std_error,group_bias_z,group_bias_threshold,group_bias_significant,group_pixel_variance,split,"
    "group_first_bounce_variance,cpu_seconds,cost,paths,orbit";

std::string studyCsv(const std::vector<StudyRow>& rows) {
    std::string out = std::string(kStudyCsvHeader) + "\n";
    for (const StudyRow& r : rows)
        out += fmt::format(
            "{},{},{},{},{},{},{},{},{},{:.6g},{},{},{:.9g},{:.6g},{:.6g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.6g},{:.6g},{:.6g},{:"
            ".4g},{:.4g},{},{:.6g},{},{:.6g},{:.6g},{:.9g},{},{}\n",
            r.scene, r.estimator, r.variant, r.sampler, r.mode, r.spp, r.repeat, r.width, r.height, r.seconds, r.rays, r.samples,
            r.meanLuminance, r.meanStdError, r.relativeBias, r.mseRaw, r.mse, r.rmse, r.relMse, r.efficiency, r.efficiencyRel,
            r.pixelVarianceWithin, r.groupRelativeBias, r.groupBiasStdError, r.groupBiasZ, r.groupBiasThreshold,
            r.groupBiasSignificant ? 1 : 0, r.groupPixelVariance, r.split, r.groupFirstBounceVariance, r.cpuSeconds, r.cost, r.paths,
            r.orbit);
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
        double meanRmse = 0;
        for (const StudyRow* r : g) {
            s.seconds += r->seconds / n;
            s.cpuSeconds += r->cpuSeconds / n;
            s.cost += r->cost / n;
            s.rays += static_cast<double>(r->rays) / n;
            s.paths += static_cast<double>(r->paths) / n;
            s.mse += r->mse / n;
            s.relMse += r->relMse / n;
            meanRmse += r->rmse / n;
        }
        double spread = 0;
        for (const StudyRow* r : g) spread += (r->rmse - meanRmse) * (r->rmse - meanRmse);
        s.rmseSpread = g.size() > 1 ? std::sqrt(spread / (n - 1) / n) : 0.0;  // standard error of the mean RMSE
        s.repeats = static_cast<int>(g.size());
        s.rmse = std::sqrt(s.mse);
        s.efficiency = s.mse > 0 && s.cost > 0 ? 1.0 / (s.mse * s.cost) : 0.0;
        s.efficiencyRel = s.relMse > 0 && s.cost > 0 ? 1.0 / (s.relMse * s.cost) : 0.0;
        s.firstBounceVariance = g.front()->groupFirstBounceVariance;
        s.relativeBias = g.front()->groupRelativeBias;
        s.biasStdError = g.front()->groupBiasStdError;
        s.biasZ = g.front()->groupBiasZ;
        s.biasSignificant = g.front()->groupBiasSignificant;
        s.pixelVariance = g.front()->groupPixelVariance;
    }
    return out;
}

namespace {

bool hasOwnSampler(const std::string& estimator) {
    const EstimatorEntry* e = findEstimator(estimator);
    return e && !e->traits.ownSampler.empty();
}

EstimatorTraits traitsOf(const std::string& estimator) {
    const EstimatorEntry* e = findEstimator(estimator);
    return e ? e->traits : EstimatorTraits{};
}

}  // namespace

const StudySummary* sameSampler(const std::vector<StudySummary>& s, const std::string& estimator, const StudySummary& like) {
    for (const auto& x : s)
        if (x.estimator == estimator && x.mode == "branch" && x.spp == like.spp && (x.sampler == like.sampler || hasOwnSampler(estimator)))
            return &x;
    return nullptr;
}

std::string factor(double x) { return x >= 10 ? fmt::format("{:.0f}x", x) : fmt::format("{:#.2g}x", x); }

bool biasedAnywhere(const std::vector<StudySummary>& s, const std::string& variant) {
    for (const auto& x : s)
        if (x.variant == variant && x.biasSignificant) return true;
    return false;
}

const StudySummary* lowestRmse(const std::vector<StudySummary>& summary, std::uint32_t spp) {
    const StudySummary* w = nullptr;
    for (const auto& s : summary)
        if (s.spp == spp && !biasedAnywhere(summary, s.variant) && (!w || s.rmse < w->rmse)) w = &s;
    return w;
}

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
    // The unbiased candidates (the symmetric estimators) against the baselines under the same sampler.
    for (const auto* s : atTop) {
        const EstimatorTraits traits = traitsOf(s->estimator);
        if (traits.role != EstimatorRole::Candidate || !traits.hasDensity) continue;
        std::vector<std::string> parts;
        for (const EstimatorEntry& other : estimatorTable())
            if (other.traits.role != EstimatorRole::Baseline)
                continue;
            else if (const StudySummary* o = sameSampler(summary, std::string(other.name), *s);
                     o && o->efficiency > 0 && o->efficiencyRel > 0)
                parts.push_back(fmt::format("{} `{}`'s by MSE ({} by relMSE)", factor(s->efficiency / o->efficiency), o->variant,
                                            factor(s->efficiencyRel / o->efficiencyRel)));
        if (!parts.empty()) text += fmt::format("`{}` reaches {}. ", s->variant, fmt::join(parts, ", "));
    }
    // Each estimator's samplers against each other.
    std::vector<std::string> samplerParts;
    for (const auto* s : atTop)
        if (!isIndependentSampler(s->sampler))
            for (const auto* o : atTop)
                if (o->estimator == s->estimator && o->mode == s->mode && isIndependentSampler(o->sampler) && s->mse > 0)
                    samplerParts.push_back(fmt::format("`{}` {} lower MSE than `{}` ({} the efficiency)", s->variant,
                                                       factor(o->mse / s->mse), o->variant, factor(s->efficiency / o->efficiency)));
    if (!samplerParts.empty()) text += fmt::format("Samplers at {} spp: {}. ", top, fmt::join(samplerParts, "; "));
    std::vector<std::string> winners;
    for (std::uint32_t spp : spps)
        if (const StudySummary* w = lowestRmse(summary, spp)) winners.push_back(fmt::format("{} spp: `{}`", spp, w->variant));
    if (!winners.empty())
        text += fmt::format(
            "At equal samples per pixel, the lowest RMSE among unbiased variants goes to {} (branch-mode symmetric "
            "estimators trace 16 to 24 paths per camera sample, so equal samples is not equal work). ",
            fmt::join(winners, ", "));
    std::vector<std::string> biased;
    for (const auto* s : atTop)
        if (s->biasSignificant)
            biased.push_back(
                fmt::format("`{}` ({:+.1f}% +- {:.1f}%, z = {:.0f})", s->variant, 100 * s->relativeBias, 100 * s->biasStdError, s->biasZ));
    if (!biased.empty())
        text += fmt::format(
            "Significantly biased against the reference (|z| > 4): {}; their error stops falling with more "
            "samples, so their efficiency means little.",
            fmt::join(biased, ", "));
    else
        text += "No variant is significantly biased (|z| > 4) against the reference.";
    return text;
}

nlohmann::json rowJson(const StudyRow& r) {
    return {{"scene", r.scene},
            {"estimator", r.estimator},
            {"variant", r.variant},
            {"sampler", r.sampler},
            {"mode", r.mode},
            {"spp", r.spp},
            {"repeat", r.repeat},
            {"width", r.width},
            {"height", r.height},
            {"seconds", r.seconds},
            {"cpu_seconds", r.cpuSeconds},
            {"cost", r.cost},
            {"rays", r.rays},
            {"samples", r.samples},
            {"paths", r.paths},
            {"orbit", r.orbit},
            {"mean_luminance", r.meanLuminance},
            {"mean_luminance_std_error", r.meanStdError},
            {"relative_bias", r.relativeBias},
            {"mse_raw", r.mseRaw},
            {"mse", r.mse},
            {"reference_sd", r.referenceSd},
            {"rmse", r.rmse},
            {"relmse", r.relMse},
            {"efficiency", r.efficiency},
            {"efficiency_relmse", r.efficiencyRel},
            {"pixel_variance_within", r.pixelVarianceWithin},
            {"group_relative_bias", r.groupRelativeBias},
            {"group_bias_std_error", r.groupBiasStdError},
            {"group_bias_z", r.groupBiasZ},
            {"group_bias_threshold", r.groupBiasThreshold},
            {"group_bias_significant", r.groupBiasSignificant},
            {"group_pixel_variance", r.groupPixelVariance},
            {"split", r.split},
            {"group_first_bounce_variance", r.groupFirstBounceVariance}};
}

nlohmann::json summaryJson(const StudySummary& s) {
    return {{"estimator", s.estimator},
            {"variant", s.variant},
            {"sampler", s.sampler},
            {"mode", s.mode},
            {"spp", s.spp},
            {"repeats", s.repeats},
            {"seconds", s.seconds},
            {"cpu_seconds", s.cpuSeconds},
            {"cost", s.cost},
            {"rays", s.rays},
            {"paths", s.paths},
            {"rmse", s.rmse},
            {"rmse_spread", s.rmseSpread},
            {"mse", s.mse},
            {"relmse", s.relMse},
            {"efficiency", s.efficiency},
            {"efficiency_relmse", s.efficiencyRel},
            {"relative_bias", s.relativeBias},
            {"bias_std_error", s.biasStdError},
            {"bias_z", s.biasZ},
            {"bias_significant", s.biasSignificant},
            {"pixel_variance", s.pixelVariance},
            {"first_bounce_variance", s.firstBounceVariance},
            {"first_bounce_share", s.firstBounceShare()}};
}

}  // namespace symphong
