// `symphong study`: options from studySchema() (study/config.h); the study shared among MPI ranks
// (distrib/study.h), Ctrl-C keeping the finished rows, the conclusion and the report's path.
#include "cli/commands.h"
#include "cli/interrupts.h"
#include "cli/schema_cli.h"
#include "distrib/mpi_job.h"
#include "distrib/study.h"
#include "render/progress.h"

#include <fmt/format.h>

namespace symphong {

void addStudyCommand(CLI::App& app, StudyOptions& o) {
    CLI::App* s =
        app.add_subcommand("study", "Compare estimators on a scene: bias, RMSE, variance, time, efficiency, with plots and a report.");
    s->footer(
        "Renders SCENE with each estimator (under each of --samplers, and the set estimators in each of --symmetric-modes)\n"
        "at each sample count, --repeats independent times, against a reference image\n"
        "(rendered once at --reference-spp with --reference-estimator and cached in DIR, or given with --reference), and\n"
        "writes into DIR: results.csv and results.json (one row per estimator x spp x repeat), convergence plots against\n"
        "samples and time with the 1/sqrt(N) slope, an efficiency bar chart (PNG and SVG), per-pixel error heat maps,\n"
        "crops of the renders, report.md (the answer in at most ten lines: each factor with its 95% interval over paired\n"
        "repeats, one line per fair pair of equal paths per camera sample; then one table per measure), details.md (every\n"
        "measure, the variance budget, equal cost) and report.html (one self-contained page: flip between the reference and\n"
        "each render, zoom, error and FLIP maps, plots, sortable tables; open it in a browser). Ctrl-C stops cleanly and keeps\n"
        "the finished rows; --resume continues an interrupted study in DIR (its finished rows kept, its reference resumed\n"
        "from DIR/reference.ckpt, written every two minutes). --reference-error stops the reference at a relative error of\n"
        "its mean instead of at --reference-spp. The reference's own noise is removed from every MSE and its spread is in\n"
        "every efficiency interval; where the report says it is large, raise --reference-spp or try --reference-splitting\n"
        "ears. Efficiency is 1/(MSE x --cost): CPU time by default, which another program\n"
        "on the machine does not bend. --target-interval H adds paired repeats at the top spp until every comparison of the\n"
        "answer is decided (ahead, behind, or equal within 10%) with a 95% interval of +-H or less, or --time / --max-repeats\n"
        "end them. --orbits 2,4,8 with --splits 2,4,8 compares symmetric-mix's orbits with phong split as many ways.\n"
        "With no arguments: the built-in Cornell box, 128x128, a few minutes on 2 cores.\n"
        "Under 'mpirun -np N' the N processes share each render; rank 0 writes the same rows (times aside) and the report\n"
        "(docs/cluster.md).\n");
    addSchemaOptions(s, o, studySchema());
}

int runStudyCommand(StudyOptions& o, const MpiJob& job) {
    o.config = toStudyConfig(o, true);
    StudyOutcome outcome;
    {
        const LauncherStopGuard guard(job, LauncherStop::StopStudy);
        outcome = runStudyDistributed(job, o.config, &gInterrupted, stderrIsTerminal());
    }
    if (!job.root()) return outcome.cancelled ? 130 : 0;
    if (outcome.cancelled) {
        fmt::print(stderr, "symphong: interrupted; {} finished row(s) kept in {}/results.csv (--resume continues)\n", outcome.rows.size(),
                   o.config.outDir);
        return 130;
    }
    for (std::string line : outcome.answer) {
        for (std::size_t p = line.find("**"); p != std::string::npos; p = line.find("**", p)) line.erase(p, 2);
        fmt::print("- {}\n", line);
    }
    fmt::print("\nreport: {0}/report.md, {0}/report.html (open it in a browser) ({1} rows{2})\n", o.config.outDir, outcome.rows.size(),
               outcome.keptRows > 0 ? fmt::format(", {} kept from the earlier run", outcome.keptRows) : "");
    if (o.config.plots && !outcome.plotted) {
        fmt::print(stderr, "symphong: error: the plots could not be made (needs python3 with matplotlib)\n");
        return 1;
    }
    return 0;
}

}  // namespace symphong
