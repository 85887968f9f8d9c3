#include "study/answer.h"

#include "estimators/registry.h"
#include "study/study_parts.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace symphong {

namespace {

std::uint32_t topSpp(const std::vector<StudySummary>& summary) {
    std::uint32_t top = 0;
    for (const auto& s : summary) top = std::max(top, s.spp);
    return top;
}

/// The summaries at `spp` of unbiased variants, most efficient first: by their efficiency ratio against the
/// yardstick over the repeats both have (the yardstick itself 1), so that the order agrees with the paired
/// factors the answer prints (a yardstick that took more repeats than a variant, for another comparison, has
/// a mean over other renders); by their own efficiency when the study has no yardstick.
std::vector<const StudySummary*> ranked(const StudyConfig& c, const std::vector<StudyRow>& rows, const std::vector<StudySummary>& summary,
                                        std::uint32_t spp, bool rel) {
    const std::vector<VariantPair> comparisons = studyComparisons(studyVariants(c));
    const auto own = [rel](const StudySummary* s) { return rel ? s->efficiencyRel : s->efficiency; };
    std::vector<std::pair<double, const StudySummary*>> out;
    for (const auto& s : summary) {
        if (s.spp != spp || biasedAnywhere(summary, s.variant) || own(&s) <= 0) continue;
        double key = own(&s);
        if (!comparisons.empty()) {
            const bool isYard = std::any_of(comparisons.begin(), comparisons.end(), [&](const VariantPair& x) { return x.against == s.variant; }) &&
                                std::none_of(comparisons.begin(), comparisons.end(), [&](const VariantPair& x) { return x.variant == s.variant; });
            const auto cmp = std::find_if(comparisons.begin(), comparisons.end(), [&](const VariantPair& x) { return x.variant == s.variant; });
            const auto r = cmp != comparisons.end()
                               ? compareVariants(rows, s.variant, cmp->against, spp, rel ? ErrorMeasure::RelMse : ErrorMeasure::Mse)
                               : std::nullopt;
            if (isYard)
                key = 1.0;
            else if (r)
                key = r->point;
            else
                continue;
        }
        out.push_back({key, &s});
    }
    std::stable_sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
    std::vector<const StudySummary*> order;
    for (const auto& [key, s] : out) order.push_back(s);
    return order;
}

std::string ratioText(const std::vector<StudyRow>& rows, const std::string& a, const std::string& b, std::uint32_t spp, ErrorMeasure m) {
    const auto r = compareVariants(rows, a, b, spp, m);
    return r ? intervalText(*r) : "-";
}

std::string mostEfficientLine(const StudyConfig& c, const std::vector<StudyRow>& rows, const std::vector<StudySummary>& summary, bool rel) {
    const std::uint32_t top = topSpp(summary);
    const ErrorMeasure m = rel ? ErrorMeasure::RelMse : ErrorMeasure::Mse;
    const auto order = ranked(c, rows, summary, top, rel);
    if (order.empty()) return {};
    const StudySummary* best = order[0];
    std::string line = fmt::format("**Most efficient by {}** at {} spp: `{}`", rel ? "relMSE" : "MSE", top, best->variant);
    if (order.size() > 1)
        line += fmt::format(", {} the efficiency of the next, `{}`", ratioText(rows, best->variant, order[1]->variant, top, m),
                            order[1]->variant);
    const std::string yard(yardstickEstimator());
    const auto isYard = [&](const StudySummary* s) { return s->estimator == yard && s->mode == "branch" && s->variant.find('+') == std::string::npos; };
    const auto y = std::find_if(order.begin(), order.end(), isYard);
    if (y != order.end() && *y != best && (order.size() < 2 || *y != order[1]))
        line += fmt::format(", {} that of `{}`", ratioText(rows, best->variant, (*y)->variant, top, m), (*y)->variant);
    return line + ".";
}

struct PairResult {
    VariantPair cmp;
    std::optional<RatioInterval> ratio;
    Verdict verdict = Verdict::Unresolved;
};

std::vector<PairResult> fairPairs(const StudyConfig& c, const std::vector<StudyRow>& rows, std::uint32_t top) {
    std::vector<PairResult> out;
    for (const VariantPair& cmp : studyComparisons(studyVariants(c)))
        if (cmp.fairPair) {
            PairResult p{cmp, compareVariants(rows, cmp.variant, cmp.against, top), Verdict::Unresolved};
            if (p.ratio) p.verdict = verdictOf(*p.ratio);
            out.push_back(p);
        }
    return out;
}

/// One word for a set of verdicts: Yes (ahead somewhere, behind nowhere), No, Sometimes (both), No gain
/// (only equal ones), Not resolved.
const char* verdictWord(int ahead, int behind, int equal) {
    return ahead > 0 && behind == 0   ? "Yes"
           : behind > 0 && ahead == 0 ? "No"
           : ahead > 0 && behind > 0  ? "Sometimes"
           : equal > 0                ? "No gain"
                                      : "Not resolved";
}

std::string paysLine(const std::vector<PairResult>& pairs) {
    if (pairs.empty())
        return "**Does symmetric sampling pay?** This study has no fair pair to answer it (a symmetric candidate and `phong` split "
               "the same number of ways: --orbits with --splits, or the spread mode beside `phong`).";
    int ahead = 0, behind = 0, equal = 0, open = 0;
    for (const PairResult& p : pairs) switch (p.verdict) {
            case Verdict::Ahead: ++ahead; break;
            case Verdict::Behind: ++behind; break;
            case Verdict::Equal: ++equal; break;
            case Verdict::Unresolved: ++open; break;
        }
    return fmt::format(
        "**Does symmetric sampling pay?** {}: against `phong` with the same paths per camera sample, the symmetric variant is ahead in "
        "{}, behind in {}, equal (within {:.0f}%) in {}{} of {} fair pairs.",
        verdictWord(ahead, behind, equal), ahead, behind, 100 * kEqualBand, equal,
        open > 0 ? fmt::format(", not resolved in {}", open) : std::string(), pairs.size());
}

/// "Does efficiency-aware splitting pay?": each variant that learns factors (`--splittings ears,ears-orbit`)
/// against its comparison (plain `phong` under its sampler), then `+ears-orbit` against `+ears` (symmetric
/// copies against independent directions, studyComparisons); empty when the study has no such variant.
std::string earsLine(const StudyConfig& c, const std::vector<StudyRow>& rows, std::uint32_t top) {
    const std::vector<StudyVariant> variants = studyVariants(c);
    std::vector<std::string> parts;
    // The verdict word, as paysLine's, from the learned variants against plain tracing (not ears-orbit against ears).
    int ahead = 0, behind = 0, equal = 0;
    const auto learns = [&](const std::string& label) {
        return std::any_of(variants.begin(), variants.end(),
                           [&](const StudyVariant& x) { return x.label == label && learnsFactors(x.splitting); });
    };
    for (const VariantPair& cmp : studyComparisons(variants)) {
        if (!learns(cmp.variant)) continue;
        const auto r = compareVariants(rows, cmp.variant, cmp.against, top);
        if (r && !learns(cmp.against)) {
            const Verdict verdict = verdictOf(*r);
            ahead += verdict == Verdict::Ahead, behind += verdict == Verdict::Behind, equal += verdict == Verdict::Equal;
        }
        parts.push_back(fmt::format("`{}` against `{}` {}", cmp.variant, cmp.against,
                                    r ? fmt::format("**{}**, {}", verdictName(verdictOf(*r)), intervalText(*r)) : "(no common repeats)"));
    }
    if (parts.empty()) return {};
    return fmt::format("**Does efficiency-aware splitting pay?** {}: {}.", verdictWord(ahead, behind, equal), fmt::join(parts, "; "));
}

std::string pairLine(const PairResult& p) {
    const std::string paths = p.cmp.paths == 1 ? "one path per camera sample" : fmt::format("{} paths per camera sample", p.cmp.paths);
    if (!p.ratio) return fmt::format("`{}` against `{}` ({}): no common repeats.", p.cmp.variant, p.cmp.against, paths);
    return fmt::format("`{}` against `{}` ({}): **{}**, {} ({} pairs).", p.cmp.variant, p.cmp.against, paths, verdictName(p.verdict),
                       intervalText(*p.ratio), p.ratio->n);
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

std::string repeatsLine(const StudyConfig& c, const std::vector<StudyRow>& rows, const std::vector<StudySummary>& summary,
                        const RepeatsNote& note) {
    const std::uint32_t top = topSpp(summary);
    int lo = 0, hi = 0;
    std::string most;
    for (const auto& s : summary)
        if (s.spp == top) {
            if (lo == 0 || s.repeats < lo) lo = s.repeats;
            if (s.repeats > hi) hi = s.repeats, most = s.variant;
        }
    std::string line = fmt::format(
        "Efficiency = 1/(MSE x {}) at {} spp; factors are ratios of means over paired repeats (repeat r of every variant has seed r), "
        "[a, b] their 95% interval (delta method). Repeats: {}",
        costWords(c.cost), top, lo == hi ? fmt::format("{} per variant", lo) : fmt::format("{} to {} (`{}` {})", lo, hi, most, hi));
    if (note.stoppedBy == "target") {
        line += fmt::format("; stopped when every comparison was decided within +-{:.0f}%", 100 * note.targetInterval);
        // As far as repeats decide it: the reference's own error, which no repeat narrows, can leave some wider.
        std::vector<std::string> limited;
        for (const VariantPair& cmp : studyComparisons(studyVariants(c))) {
            if (biasedAt(rows, cmp.variant, top) || biasedAt(rows, cmp.against, top)) continue;
            const auto r = compareVariants(rows, cmp.variant, cmp.against, top);
            if (r && !settled(*r, note.targetInterval)) limited.push_back(fmt::format("`{}` against `{}`", cmp.variant, cmp.against));
        }
        if (!limited.empty())
            line +=
                fmt::format(" by its repeats; the reference's own error leaves {} wider (raise --reference-spp)", fmt::join(limited, ", "));
    } else if (note.stoppedBy == "time" || note.stoppedBy == "max-repeats") {
        std::set<std::string> open = variantsToRepeat(rows, top, studyComparisons(studyVariants(c)), note.targetInterval);
        line += fmt::format("; stopped by {} before every comparison was decided within +-{:.0f}%{}",
                            note.stoppedBy == "time" ? "the --time budget" : "--max-repeats", 100 * note.targetInterval,
                            open.empty() ? std::string() : fmt::format(" (still open: `{}`)", fmt::join(open, "`, `")));
    } else if (note.stoppedBy == "cancelled")
        line += "; interrupted";
    return line + ".";
}

}  // namespace

double median(std::vector<double> v) {
    const std::size_t half = v.size() / 2;
    std::nth_element(v.begin(), v.begin() + static_cast<long>(half), v.end());
    if (v.size() % 2) return v[half];
    return 0.5 * (*std::max_element(v.begin(), v.begin() + static_cast<long>(half)) + v[half]);
}

std::string costWords(StudyCost cost) {
    switch (cost) {
        case StudyCost::Cpu: return "CPU time";
        case StudyCost::Wall: return "wall time";
        case StudyCost::Rays: return "rays traced";
    }
    return "cost";
}

std::vector<std::string> studyAnswer(const StudyConfig& c, const std::vector<StudyRow>& rows, const std::vector<StudySummary>& summary,
                                     const RepeatsNote& repeats) {
    if (summary.empty()) return {"No results."};
    const std::vector<PairResult> pairs = fairPairs(c, rows, topSpp(summary));
    std::vector<std::string> lines;
    const std::string byMse = mostEfficientLine(c, rows, summary, false), byRel = mostEfficientLine(c, rows, summary, true);
    for (const std::string& l : {byMse, byRel, paysLine(pairs), earsLine(c, rows, topSpp(summary))})
        if (!l.empty()) lines.push_back(l);
    // At most ten lines: the pairs take what the others leave (the relMSE line goes first when they need it).
    const std::size_t tail = 2;
    if (lines.size() + pairs.size() + tail > 10 && !byMse.empty() && !byRel.empty()) lines.erase(lines.begin() + 1);
    const std::size_t room = 10 - std::min<std::size_t>(10, lines.size() + tail);
    for (std::size_t i = 0; i < pairs.size() && i < room; ++i) lines.push_back(pairLine(pairs[i]));
    if (pairs.size() > room)
        lines.back() += fmt::format(" ({} more fair pairs in results.json's \"comparisons\".)", pairs.size() - room);
    lines.push_back(biasLine(summary));
    lines.push_back(repeatsLine(c, rows, summary, repeats));
    return lines;
}

nlohmann::json answerComparisonsJson(const StudyConfig& c, const std::vector<StudyRow>& rows, const std::vector<StudySummary>& summary) {
    nlohmann::json out = nlohmann::json::array();
    const std::uint32_t top = topSpp(summary);
    for (const VariantPair& cmp : studyComparisons(studyVariants(c))) {
        nlohmann::json j = {{"variant", cmp.variant},
                            {"against", cmp.against},
                            {"fair_pair", cmp.fairPair},
                            {"paths_per_sample", cmp.paths},
                            {"spp", top},
                            {"repeats_variant", repeatsOf(rows, cmp.variant, top)},
                            {"repeats_against", repeatsOf(rows, cmp.against, top)},
                            {"biased", biasedAt(rows, cmp.variant, top) || biasedAt(rows, cmp.against, top)}};
        for (const auto& [key, m] : {std::pair{"mse", ErrorMeasure::Mse}, std::pair{"relmse", ErrorMeasure::RelMse}}) {
            const auto r = compareVariants(rows, cmp.variant, cmp.against, top, m);
            j[key] = r ? nlohmann::json{{"ratio", r->point}, {"lo", r->lo}, {"hi", r->hi}, {"pairs", r->n}, {"verdict", verdictName(verdictOf(*r))}}
                       : nlohmann::json(nullptr);
        }
        out.push_back(j);
    }
    return out;
}

std::vector<ReportTable> studyTables(const StudyConfig& c, const std::vector<StudyRow>& rows, const std::vector<StudySummary>& summary) {
    std::vector<ReportTable> tables;
    std::vector<std::string> columns = {"variant"};
    for (std::uint32_t spp : c.spps) columns.push_back(fmt::format("{} spp", spp));
    const std::vector<StudyVariant> variants = studyVariants(c);
    const std::vector<VariantPair> comparisons = studyComparisons(variants);
    const std::string yard(yardstickEstimator());
    for (const bool rel : {false, true}) {
        ReportTable t{fmt::format("Efficiency by {}, relative to `{}` (95% interval)", rel ? "relMSE" : "MSE", yard),
                      fmt::format("1/({} x {}), the ratio of the means over the repeats both have, against `{}` under the same sampler.",
                                  rel ? "relMSE" : "MSE", costWords(c.cost), yard),
                      columns,
                      {}};
        for (const StudyVariant& v : variants) {
            std::vector<ReportCell> row = {{fmt::format("`{}`{}", v.label, biasedAnywhere(summary, v.label) ? " (biased)" : ""), {}}};
            const auto cmp = std::find_if(comparisons.begin(), comparisons.end(), [&](const VariantPair& x) { return x.variant == v.label; });
            const bool isYard = std::any_of(comparisons.begin(), comparisons.end(), [&](const VariantPair& x) { return x.against == v.label; }) &&
                                v.estimator == yard && v.split == 1;
            for (std::uint32_t spp : c.spps) {
                if (isYard && repeatsOf(rows, v.label, spp) > 0) {
                    row.push_back({"1x", 1.0});
                    continue;
                }
                const auto r = cmp != comparisons.end()
                                   ? compareVariants(rows, v.label, cmp->against, spp, rel ? ErrorMeasure::RelMse : ErrorMeasure::Mse)
                                   : std::nullopt;
                row.push_back(r ? ReportCell{intervalText(*r), r->point} : ReportCell{"-", {}});
            }
            t.rows.push_back(std::move(row));
        }
        tables.push_back(std::move(t));
    }
    ReportTable rmse{"RMSE of luminance (95% interval)", "The square root of the mean MSE over the repeats, the reference's own noise removed.",
                     columns, {}};
    for (const StudyVariant& v : variants) {
        std::vector<ReportCell> row = {{fmt::format("`{}`", v.label), {}}};
        for (std::uint32_t spp : c.spps) {
            std::vector<double> mse;
            for (const StudyRow& r : rows)
                if (r.variant == v.label && r.spp == spp) mse.push_back(r.mse);
            if (mse.empty()) {
                row.push_back({"-", {}});
                continue;
            }
            const RatioInterval m = meanInterval(mse);
            const double p = std::sqrt(m.point);
            row.push_back({m.lo == m.hi ? fmt::format("{:.3g}", p) : fmt::format("{:.3g} [{:.3g}, {:.3g}]", p, std::sqrt(m.lo), std::sqrt(m.hi)), p});
        }
        rmse.rows.push_back(std::move(row));
    }
    tables.push_back(std::move(rmse));
    const std::uint32_t top = topSpp(summary);
    ReportTable cost{fmt::format("Repeats and cost at {} spp", top),
                     fmt::format("Means over the repeats of each render's wall time, the CPU time of its threads, its rays and the paths "
                                 "each camera sample started; efficiency divides by {}.",
                                 costWords(c.cost)),
                     {"variant", "repeats", "wall (s)", "CPU (s)", "Mrays", "paths per sample", "efficiency"},
                     {}};
    for (const StudySummary& s : summary)
        if (s.spp == top)
            cost.rows.push_back({{fmt::format("`{}`", s.variant), {}},
                                 {fmt::format("{}", s.repeats), static_cast<double>(s.repeats)},
                                 {fmt::format("{:.3g}", s.seconds), s.seconds},
                                 {fmt::format("{:.3g}", s.cpuSeconds), s.cpuSeconds},
                                 {fmt::format("{:.3g}", s.rays / 1e6), s.rays / 1e6},
                                 {fmt::format("{:.3g}", s.paths / std::max(1.0, static_cast<double>(c.width) * c.height * s.spp)),
                                  s.paths / std::max(1.0, static_cast<double>(c.width) * c.height * s.spp)},
                                 {fmt::format("{:.3g}", s.efficiency), s.efficiency}});
    tables.push_back(std::move(cost));
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
