// The study's report (report.md: the answer first, then one table per measure; details.md: every measure,
// the variance budget, equal time and the plots) and the plots themselves (the embedded scripts/plot_study.py).
#include "estimators/registry.h"
#include "io/files.h"
#include "sampling/sampler_registry.h"
#include "study/answer.h"
#include "study/config.h"
#include "study/plot_script.h"
#include "study/study_parts.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace fs = std::filesystem;

namespace symphong {

namespace {

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

std::string reportHeader(const ReportInputs& in) {
    const StudyConfig& c = in.config;
    const std::string& sceneName = in.sceneName;
    const std::vector<StudySummary>& summary = in.summary;
    const bool cancelled = in.cancelled;
    const int processes = in.processes;
    std::string md = fmt::format("# Estimator study: {}\n\n", sceneName);
    if (cancelled) md += "**Interrupted**: these are the rows finished before the study was stopped.\n\n";
    md += fmt::format(
        "Scene `{}`, {}x{} pixels, max depth {}, {} paired repeat(s) per variant and sample count{}, seed {}. {}\n"
        "Efficiency is 1/(MSE x {}). A variant is an estimator under a sampler (`@sampler`), in spread mode for the set estimators "
        "(`+spread`), with R symmetric copies of one point traced from each camera sample (`+orbitR`), with "
        "K directions from each camera sample's first hit (`+splitK`), with splitting and roulette learned by EARS (`+ears`, "
        "`+ears-orbit`).\n"
        "Command: `symphong study{}`.\n\n",
        c.scene, c.width, c.height, c.maxDepth, c.repeats,
        c.targetInterval > 0 ? fmt::format(" (more at the top spp, up to a 95% interval of +-{:.0f}%: the answer says how many)", 100 * c.targetInterval)
                             : std::string(),
        c.seed, in.reference.note, costWords(c.cost), studyCommandLine(c));
    if (processes > 1)
        md += fmt::format("Each render was shared among {} processes (MPI ranks); times are the whole job's.\n\n", processes);
    md += referenceNoiseWords(summary, in.reference);
    return md;
}

std::string reportPlots(const ReportInputs& in) {
    std::string md;
    const bool plotted = in.plotted;
    const std::uint32_t heatSpp = in.heatSpp;
    if (plotted) {
        md +=
            "## Convergence\n\n![RMSE against samples per pixel](convergence_spp.png)\n\n"
            "![RMSE against render time](convergence_time.png)\n\n"
            "## Efficiency\n\n![Efficiency relative to phong](efficiency.png)\n\n";
        md +=
            fmt::format("## Where the error is ({} spp)\n\n![Per-pixel relative error](heatmaps.png)\n\n![Crops](crops.png)\n\n", heatSpp);
    } else if (!in.config.plots) {
        md += "Plots were not asked for (`--no-plots`); `python3 scripts/plot_study.py` on this folder draws them.\n\n";
    } else {
        md += "Plots were not made (no python3 with matplotlib); run `python3 scripts/plot_study.py` on this folder.\n\n";
    }
    return md;
}

std::string reportBudget(const ReportInputs& in) {
    const StudyConfig& c = in.config;
    const std::vector<StudySummary>& summary = in.summary;
    std::string md;
    // The variance budget: where the remaining variance comes from.
    std::string budget;
    for (const auto& s : summary)
        if (s.firstBounceShare() >= 0)
            budget += fmt::format("| {} | {} | {:.3g} | {:.3g} | {:.0f}% |\n", s.variant, s.spp, s.pixelVariance, s.firstBounceVariance,
                                  100 * s.firstBounceShare());
    if (!budget.empty())
        md += fmt::format(
            "## Variance budget ({} pairs)\n\nMean pixel variance (luminance) across the repeats, and the part of it that "
            "comes from the first-bounce directions: the mean of (Y_1 - Y_2)^2 / 2 over pairs of renders that differ only in "
            "the first hit's estimator numbers (`--first-bounce-stream` 1 and 2), every other decision of the path keeping "
            "its numbers. The rest comes from the pixel position, light sampling and the deeper bounces (law of total "
            "variance). With few repeats each figure is uncertain by tens of percent.\n\n"
            "| variant | spp | pixel variance | from the first bounce | share |\n|---|---:|---:|---:|---:|\n{}\n",
            c.budgetPairs, budget);
    return md;
}

std::string reportEqualSamples(const ReportInputs& in) {
    const std::vector<StudySummary>& summary = in.summary;
    const std::string yard(yardstickEstimator());
    std::string md = fmt::format(
        "## Equal samples\n\nMeans over the repeats; RMSE of luminance against the reference (its own noise removed), "
        "relMSE = mean of (Y - Y_ref)^2 / (Y_ref^2 + 0.01), bias of the mean image with its standard error (flagged when "
        "|z| > 4), efficiency 1/(MSE x {0}) from the means, relative to `{1}` under the same sampler at the same spp; the last "
        "column is the same with relMSE in place of MSE.\n\n"
        "| variant | spp | repeats | wall (s) | CPU (s) | Mrays | RMSE | relMSE | pixel variance | rel. bias | efficiency vs {1} | relMSE "
        "efficiency vs {1} |\n"
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n",
        costWords(in.config.cost), yard);
    for (const auto& s : summary) {
        const StudySummary* y = sameSampler(summary, yard, s);
        md += fmt::format("| {} | {} | {} | {:.3g} | {:.3g} | {:.3g} | {:.4g} | {:.4g} | {:.3g} | {:+.2f}% +- {:.2f}%{} | {} | {} |\n",
                          s.variant, s.spp, s.repeats, s.seconds, s.cpuSeconds, s.rays / 1e6, s.rmse, s.relMse, s.pixelVariance,
                          100 * s.relativeBias, 100 * s.biasStdError, s.biasSignificant ? " **biased**" : "",
                          y && y->efficiency > 0 ? factor(s.efficiency / y->efficiency) : "-",
                          y && y->efficiencyRel > 0 ? factor(s.efficiencyRel / y->efficiencyRel) : "-");
    }
    return md;
}

std::string reportEqualTime(const ReportInputs& in) {
    const StudyConfig& c = in.config;
    const std::vector<StudySummary>& summary = in.summary;
    std::string md;
    // Equal cost: efficiency is about constant in spp for an unbiased estimator, so the MSE reachable at
    // cost T is about 1/(efficiency x T); T = the yardstick's cost at the highest spp.
    std::uint32_t top = 0;
    for (const auto& s : summary) top = std::max(top, s.spp);
    const StudySummary* ref = nullptr;
    for (const auto& s : summary)
        if (s.spp == top && s.estimator == yardstickEstimator() && s.variant.find('+') == std::string::npos && !ref) ref = &s;
    if (!ref && !summary.empty()) ref = &summary.front();
    if (ref && ref->cost > 0 && ref->efficiency > 0) {
        const double T = ref->cost;
        const std::string unit = c.cost == StudyCost::Rays ? " rays" : " s";
        md += fmt::format(
            "\n## Equal cost\n\nRMSE each variant would reach at a cost ({}) of {:.3g}{} (what `{}` took at {} spp), from its "
            "efficiency at the sample count whose cost is closest: RMSE_T = sqrt(1/(efficiency x T)).\n\n"
            "| variant | from spp | RMSE at equal cost | vs `{}` |\n|---|---:|---:|---:|\n",
            costWords(c.cost), T, unit, ref->variant, top, ref->variant);
        const double refRmse = std::sqrt(1.0 / (ref->efficiency * T));
        for (const StudyVariant& v : studyVariants(c)) {
            const std::string& est = v.label;
            const StudySummary* bestFit = nullptr;
            for (const auto& s : summary)
                if (s.variant == est && s.cost > 0 && s.efficiency > 0 &&
                    (!bestFit || std::abs(std::log(s.cost / T)) < std::abs(std::log(bestFit->cost / T))))
                    bestFit = &s;
            if (!bestFit) continue;
            const double rmseT = std::sqrt(1.0 / (bestFit->efficiency * T));
            md += fmt::format("| {}{} | {} | {:.4g} | {:.2f}x |\n", est, biasedAnywhere(summary, est) ? " (biased)" : "", bestFit->spp,
                              rmseT, rmseT / refRmse);
        }
    }
    return md;
}

}  // namespace

std::string referenceNoiseWords(const std::vector<StudySummary>& summary, const Reference& reference) {
    const StudySummary* least = nullptr;  // the smallest MSE, on which the reference's error weighs most
    for (const auto& s : summary)
        if (s.mse > 0 && (!least || s.mse < least->mse)) least = &s;
    if (!least || !(reference.noise >= 0.5 * least->mse)) return {};
    // Above a tenth of the MSE (one standard deviation) it widens those intervals more than the repeats do at
    // the study's usual +-10% target.
    const bool warn = reference.noiseSd > 0.1 * least->mse;
    return fmt::format(
        "{} reference's own noise ({:.3g}) is at least half of some estimators' squared error (`{}` at {} spp: {:.3g}). It is "
        "removed from every MSE; what is left of it, one error shared by every render (standard deviation {:.3g}, {:.1f}% of that "
        "MSE), no number of repeats averages away, and the efficiency intervals by MSE include it.{}\n\n",
        warn ? "**Warning:** the" : "The", reference.noise, least->variant, least->spp, least->mse, reference.noiseSd,
        100 * reference.noiseSd / least->mse,
        warn ? " Raise --reference-spp, or render the reference with --reference-splitting ears where EARS splits." : "");
}

std::string reportMarkdown(const ReportInputs& in) {
    std::string md = reportHeader(in) + "## The answer\n\n";
    for (const std::string& line : in.answer) md += "- " + line + "\n";
    md += in.cancelled      ? "\nreport.html is written when the study finishes (`--resume` continues it). "
          : !in.config.page ? "\nNo report.html (`--no-page`); run the study without it for the page of every render. "
                            : "\nSee it: [report.html](report.html) (every render beside the reference, error and FLIP maps, zoom, plots). ";
    md += "Details: [details.md](details.md) (every measure of every group, the variance budget, equal cost, plots).\n\n";
    for (const ReportTable& t : in.tables) md += tableMarkdown(t);
    return md;
}

std::string reportDetailsMarkdown(const ReportInputs& in) {
    std::string md = reportHeader(in);
    md += "[Back to the report](report.md).\n\n## Conclusion in words\n\n" + in.conclusion + "\n\n";
    md += reportPlots(in) + reportBudget(in) + reportEqualSamples(in) + reportEqualTime(in);
    md +=
        "\nFiles: `results.csv` and `results.json` (one row per estimator x spp x repeat), `reference.exr` (+ `reference.json`), "
        "`renders/` (each variant's first repeat at each spp, as EXR, and a PNG at the heat maps' spp), `heatmaps/`, `report.html`.\n";
    return md;
}

bool makePlots(const StudyConfig& c, const fs::path& dir) {
    const std::string py = findPython(c.python);
    if (py.empty()) {
        fmt::print(stderr,
                   "symphong: warning: no python3 with matplotlib found (Debian: apt-get install python3-matplotlib); "
                   "no plots were made\n");
        return false;
    }
    const std::string script = (dir / "plot_study.py").string();
    writeFile(script, kPlotStudyScript);
    const std::string cmd = fmt::format("'{}' '{}' '{}'", py, script, dir.string());
    const bool plotted = std::system(cmd.c_str()) == 0;
    if (!plotted) fmt::print(stderr, "symphong: warning: the plotting script failed: {}\n", cmd);
    return plotted;
}

}  // namespace symphong
