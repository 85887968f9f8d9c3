#include "study/answer.h"

#include "estimators/registry.h"
#include "study/study_parts.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <random>

namespace symphong {

namespace {


/// A measure of one render, by name.
using Measure = double StudyRow::*;

std::vector<double> repeatsOf(const std::vector<StudyRow>& rows, const std::string& variant, std::uint32_t spp, Measure m) {
    std::vector<double> out;
    for (const StudyRow& r : rows)
        if (r.variant == variant && r.spp == spp) out.push_back(r.*m);
    return out;
}

EstimatorRole roleOf(const std::string& estimator) {
    const EstimatorEntry* e = findEstimator(estimator);
    return e && e->traits.hasDensity ? e->traits.role : EstimatorRole::Other;
}

std::uint32_t topSpp(const std::vector<StudySummary>& summary) {
    std::uint32_t top = 0;
    for (const auto& s : summary) top = std::max(top, s.spp);
    return top;
}

/// The unbiased summary at `spp` with the largest median of `eff` among those `keep` accepts.
template <class Keep>
const StudySummary* mostEfficient(const std::vector<StudySummary>& summary, std::uint32_t spp, double StudySummary::*eff, Keep keep) {
    const StudySummary* best = nullptr;
    for (const auto& s : summary)
        if (s.spp == spp && !biasedAnywhere(summary, s.variant) && s.*eff > 0 && keep(s) && (!best || s.*eff > best->*eff)) best = &s;
    return best;
}

/// "`a` ... F [lo, hi] ..." for the ratio of a's repeats of measure m to b's.
std::string ratioText(const std::vector<StudyRow>& rows, const StudySummary& a, const StudySummary& b, Measure m, std::uint64_t seed,
                      int draws) {
    const auto r = bootstrapRatio(repeatsOf(rows, a.variant, a.spp, m), repeatsOf(rows, b.variant, b.spp, m), seed, draws);
    return r ? intervalText(*r) : "-";
}

std::string mostEfficientLine(const std::vector<StudyRow>& rows, const std::vector<StudySummary>& summary, bool rel, int draws) {
    const std::uint32_t top = topSpp(summary);
    double StudySummary::*eff = rel ? &StudySummary::efficiencyRel : &StudySummary::efficiency;
    const Measure m = rel ? &StudyRow::efficiencyRel : &StudyRow::efficiency;
    const StudySummary* best = mostEfficient(summary, top, eff, [](const StudySummary&) { return true; });
    if (!best) return {};
    std::string line = fmt::format("**Most efficient by {}** at {} spp: `{}`", rel ? "relMSE" : "MSE", top, best->variant);
    const StudySummary* second = mostEfficient(summary, top, eff, [&](const StudySummary& s) { return &s != best; });
    if (second) line += fmt::format(", {} the efficiency of the next, `{}`", ratioText(rows, *best, *second, m, 11, draws), second->variant);
    const StudySummary* yard = sameSampler(summary, std::string(yardstickEstimator()), *best);
    if (yard && yard != best && yard != second)
        line += fmt::format(", {} that of `{}`", ratioText(rows, *best, *yard, m, 12, draws), yard->variant);
    return line + ".";
}

std::string paysLine(const std::vector<StudyRow>& rows, const std::vector<StudySummary>& summary, int draws) {
    const std::uint32_t top = topSpp(summary);
    const StudySummary* cand =
        mostEfficient(summary, top, &StudySummary::efficiency, [](const StudySummary& s) { return roleOf(s.estimator) == EstimatorRole::Candidate; });
    const StudySummary* base =
        mostEfficient(summary, top, &StudySummary::efficiency, [](const StudySummary& s) { return roleOf(s.estimator) == EstimatorRole::Baseline; });
    if (!cand || !base) return "**Does symmetric sampling pay?** This study has no unbiased symmetric variant or no baseline to answer it.";
    const auto r = bootstrapRatio(repeatsOf(rows, cand->variant, top, &StudyRow::efficiency),
                                  repeatsOf(rows, base->variant, top, &StudyRow::efficiency), 13, draws);
    if (!r) return {};
    const char* verdict = r->lo > 1 ? "Yes" : r->hi < 1 ? "No" : r->lo == r->hi ? "Undecided (one repeat, no interval)"
                                                                                 : "Not resolved at 95%";
    return fmt::format(
        "**Does symmetric sampling pay?** {}: the most efficient symmetric variant, `{}`, reaches {} the efficiency of the best "
        "baseline, `{}`, by MSE ({} by relMSE).",
        verdict, cand->variant, intervalText(*r), base->variant, ratioText(rows, *cand, *base, &StudyRow::efficiencyRel, 14, draws));
}

std::string lowestRmseLine(const std::vector<StudySummary>& summary, const std::vector<std::uint32_t>& spps) {
    std::vector<std::string> winners;
    for (std::uint32_t spp : spps)
        if (const StudySummary* w = lowestRmse(summary, spp)) winners.push_back(fmt::format("{} spp `{}`", spp, w->variant));
    if (winners.empty()) return {};
    return fmt::format("**Lowest RMSE at equal samples**: {} (not equal work: a set estimator traces several paths per sample).",
                       fmt::join(winners, ", "));
}

std::string biasLine(const std::vector<StudySummary>& summary) {
    const std::uint32_t top = topSpp(summary);
    std::vector<std::string> biased;
    for (const auto& s : summary)
        if (s.spp == top && s.biasSignificant)
            biased.push_back(fmt::format("`{}` {:+.1f}% +- {:.1f}%", s.variant, 100 * s.relativeBias, 100 * s.biasStdError));
    if (biased.empty()) return "**Bias**: no variant is significantly biased against the reference (|z| > 4).";
    return fmt::format("**Bias** (|z| > 4 at {} spp, left out above): {}.", top, fmt::join(biased, ", "));
}

}  // namespace

double median(std::vector<double> v) {
    const std::size_t half = v.size() / 2;
    std::nth_element(v.begin(), v.begin() + static_cast<long>(half), v.end());
    if (v.size() % 2) return v[half];
    return 0.5 * (*std::max_element(v.begin(), v.begin() + static_cast<long>(half)) + v[half]);
}

std::optional<RatioInterval> bootstrapRatio(const std::vector<double>& a, const std::vector<double>& b, std::uint64_t seed, int draws) {
    if (a.empty() || b.empty() || !(median(b) > 0)) return std::nullopt;
    RatioInterval r;
    r.point = median(a) / median(b);
    if ((a.size() < 2 && b.size() < 2) || draws <= 0) {
        r.lo = r.hi = r.point;
        return r;
    }
    std::mt19937_64 rng(seed);
    std::vector<double> ratios, ra(a.size()), rb(b.size());
    ratios.reserve(static_cast<std::size_t>(draws));
    for (int d = 0; d < draws; ++d) {
        for (double& x : ra) x = a[rng() % a.size()];
        for (double& x : rb) x = b[rng() % b.size()];
        const double mb = median(rb);
        ratios.push_back(mb > 0 ? median(ra) / mb : std::numeric_limits<double>::infinity());
    }
    std::sort(ratios.begin(), ratios.end());
    r.lo = ratios[static_cast<std::size_t>(0.025 * draws)];
    r.hi = ratios[static_cast<std::size_t>(0.975 * draws) - 1];
    return r;
}

std::string intervalText(const RatioInterval& r) {
    if (r.lo == r.hi) return factor(r.point);
    return fmt::format("{} [{:.2g}, {:.2g}]", factor(r.point), r.lo, r.hi);
}

std::vector<std::string> studyAnswer(const StudyConfig& c, const std::vector<StudyRow>& rows, const std::vector<StudySummary>& summary,
                                     int draws) {
    if (summary.empty()) return {"No results."};
    std::vector<std::string> lines;
    for (const std::string& l : {mostEfficientLine(rows, summary, false, draws), mostEfficientLine(rows, summary, true, draws),
                                 paysLine(rows, summary, draws),
                                 lowestRmseLine(summary, c.spps), biasLine(summary)})
        if (!l.empty()) lines.push_back(l);
    if (draws <= 0)
        lines.push_back("Factors are ratios of medians over the repeats, without intervals (an interrupted study's report).");
    else if (c.repeats > 1)
        lines.push_back(fmt::format("Factors are ratios of medians over {} repeats; [a, b] is the 95% bootstrap interval.", c.repeats));
    else
        lines.push_back("One repeat per variant: factors without intervals (run with --repeats 5 or more for them).");
    return lines;
}

std::vector<ReportTable> studyTables(const StudyConfig& c, const std::vector<StudyRow>& rows, const std::vector<StudySummary>& summary,
                                     int draws) {
    std::vector<ReportTable> tables;
    std::vector<std::string> columns = {"variant"};
    for (std::uint32_t spp : c.spps) columns.push_back(fmt::format("{} spp", spp));
    const std::string yard(yardstickEstimator());
    for (const bool rel : {false, true}) {
        ReportTable t{fmt::format("Efficiency by {}, relative to `{}` (95% interval)", rel ? "relMSE" : "MSE", yard),
                      fmt::format("1/({} x time) of each render, the median over the repeats, over that of `{}` under the same sampler.",
                                  rel ? "relMSE" : "MSE", yard),
                      columns,
                      {}};
        const Measure m = rel ? &StudyRow::efficiencyRel : &StudyRow::efficiency;
        for (const StudyVariant& v : studyVariants(c)) {
            std::vector<ReportCell> row = {{fmt::format("`{}`{}", v.label, biasedAnywhere(summary, v.label) ? " (biased)" : ""), {}}};
            for (std::uint32_t spp : c.spps) {
                const StudySummary* s = nullptr;
                for (const auto& x : summary)
                    if (x.variant == v.label && x.spp == spp) s = &x;
                const StudySummary* y = s ? sameSampler(summary, yard, *s) : nullptr;
                const auto r = s && y ? bootstrapRatio(repeatsOf(rows, s->variant, spp, m), repeatsOf(rows, y->variant, spp, m), 21 + spp, draws)
                                      : std::nullopt;
                row.push_back(r ? ReportCell{s == y ? std::string("1x") : intervalText(*r), r->point} : ReportCell{"-", {}});
            }
            t.rows.push_back(std::move(row));
        }
        tables.push_back(std::move(t));
    }
    ReportTable rmse{"RMSE of luminance (95% interval)", "The median over the repeats, the reference's own noise removed.", columns, {}};
    for (const StudyVariant& v : studyVariants(c)) {
        std::vector<ReportCell> row = {{fmt::format("`{}`", v.label), {}}};
        for (std::uint32_t spp : c.spps) {
            const auto r = bootstrapRatio(repeatsOf(rows, v.label, spp, &StudyRow::rmse), {1.0}, 31 + spp, draws);
            row.push_back(r ? ReportCell{r->lo == r->hi ? fmt::format("{:.3g}", r->point)
                                                        : fmt::format("{:.3g} [{:.3g}, {:.3g}]", r->point, r->lo, r->hi),
                                         r->point}
                            : ReportCell{"-", {}});
        }
        rmse.rows.push_back(std::move(row));
    }
    tables.push_back(std::move(rmse));
    return tables;
}

std::string tableMarkdown(const ReportTable& t) {
    std::string md = fmt::format("## {}\n\n{}\n\n| {} |\n|---|", t.title, t.note, fmt::join(t.columns, " | "));
    for (std::size_t i = 1; i < t.columns.size(); ++i) md += "---:|";
    md += "\n";
    for (const auto& row : t.rows) {
        std::vector<std::string> cells;
        for (const ReportCell& c : row) cells.push_back(c.text);
        md += fmt::format("| {} |\n", fmt::join(cells, " | "));
    }
    return md + "\n";
}

}  // namespace symphong
