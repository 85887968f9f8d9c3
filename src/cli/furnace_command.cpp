// `symphong furnace`: options from furnaceSchema() (study/config.h); one line per cell as it finishes,
// and the rows as JSON with --json.
#include "cli/commands.h"
#include "cli/schema_cli.h"
#include "io/files.h"
#include "io/input_error.h"
#include "study/environment.h"
#include "study/furnace.h"

#include <fmt/format.h>

namespace symphong {

void addFurnaceCommand(CLI::App& app, FurnaceOptions& o) {
    CLI::App* f = app.add_subcommand("furnace", "Measure reflected-radiance estimators at one shading point against exact values.");
    f->footer(
        "Evaluates each estimator M times at one shading point (grey Phong material, view angle THETA from the normal,\n"
        "azimuth PHI) under an incoming radiance whose reflected value is known exactly, and prints the mean, its\n"
        "standard error, the exact value, the relative bias and its z-score, the variance of one estimate, the\n"
        "variance per direction (var x directions: estimators compared at an equal number of directions), the\n"
        "time per estimate and the efficiency 1/(var x time). One estimate is one call of a set-returning estimator\n"
        "(paper, symmetric* in branch mode), the mean of one whole spread set (spread mode), or the mean of --directions\n"
        "calls of the others. Estimate r is pixel r of --sampler and call i its sample i, so a stratified or sobol sampler\n"
        "stratifies the calls of an estimate.\n"
        "Environments: constant (L = 1), gradient (quadratic sky), disk (small disk light), band (horizon band),\n"
        "halfspace. --grid runs n in {1,10,100,1000,10000} x theta in {0,30,60,85}.\n");
    addSchemaOptions(f, o, furnaceSchema());
}

int runFurnaceCommand(const FurnaceOptions& o) {
    FurnaceTable table = toFurnaceTable(o, true);
    for (const auto& e : table.estimators) estimatorOrInputError(e, table.options);
    if (!o.json.empty()) {
        try {
            checkCanCreate(o.json);  // fails now, not after the run, if it cannot be written
        } catch (const InputError& e) {
            throw InputError(fmt::format("--json {}", e.what()));
        }
    }
    fmt::print("rho_d {}  rho_s {}  repeats {}  seed {}  sampler {}  (one-direction estimators: {} calls per estimate)\n", table.rhoD,
               table.rhoS, table.repeats, table.seed, table.sampler, table.directions);
    fmt::print("{:<18} {:<10} {:>6} {:>5} {:>6} {:>11} {:>10} {:>11} {:>9} {:>8} {:>10} {:>10} {:>9} {:>10}\n", "estimator", "environmt",
               "n", "theta", "dirs", "estimate", "std.err", "exact", "rel.bias", "z", "var(1 est)", "var x dirs", "us/est", "efficiency");
    const auto rows = runFurnaceTable(table, [](const FurnaceResult& r) {
        fmt::print(
            "{:<18} {:<10} {:>6} {:>5} {:>6.1f} {:>11.6f} {:>10.2e} {:>11.6f} {:>+8.2f}% {:>8.2f} {:>10.3e} {:>10.3e} {:>9.3f} {:>10.3e}\n",
            r.estimator, r.environment, r.n, r.thetaDeg, r.directionsPerEstimate, r.estimate, r.stdError, r.exact, 100 * r.relativeBias,
            r.z, r.variance, r.varianceTimesDirections, 1e6 * r.secondsPerEstimate, r.efficiency);
    });
    if (!o.json.empty()) writeFile(o.json, furnaceJson(rows));
    return 0;
}

}  // namespace symphong
