// study/furnace.h — the single-point furnace: one shading point, one material, one environment with an
// exact answer, M independent estimates. Measures bias (with its z-score), the variance of one estimate,
// the variance per direction (equal-direction comparison) and the time per estimate.
#pragma once

#include "estimators/estimator.h"
#include "study/environment.h"

#include <atomic>
#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <vector>

namespace symphong {

struct FurnaceSetup {
    std::string estimator = "symmetric";
    EstimatorOptions options;
    double rhoD = 0.3, rhoS = 0.6, n = 10, thetaDeg = 30;  ///< grey material and view angle from the normal
    double phiDeg = 0;                                     ///< view azimuth
    int repeats = 10000;                                   ///< M independent estimates
    std::uint64_t seed = 1;
    int directions = 16;  ///< estimators that return one direction per call are called this many times per estimate
    std::string sampler = std::string(kDefaultSampler);  ///< estimate r is pixel r, call i its sample i
    /// The exact reflected radiance when the caller already has it (several runs of one cell): skips
    /// its quadrature. NaN: computed.
    double knownExact = std::numeric_limits<double>::quiet_NaN();
};

struct FurnaceResult {
    std::string estimator, environment, sampler;
    double rhoD = 0, rhoS = 0, n = 0, thetaDeg = 0;
    int repeats = 0;
    double estimate = 0, stdError = 0, exact = 0;
    double relativeBias = 0, z = 0;
    double variance = 0;  ///< variance of one estimate
    double directionsPerEstimate = 0;
    double varianceTimesDirections = 0;  ///< per-direction variance: compares estimators at equal directions
    double secondsPerEstimate = 0;
    double efficiency = 0;  ///< 1 / (variance * seconds per estimate)
};

/// Runs M estimates. One estimate is one call of a set-returning estimator (paper, symmetric: its whole
/// set of directions), the mean of one whole spread set's calls (spread mode: P N' calls), or the mean of
/// `directions` calls of a one-direction estimator. Estimate r is pixel r of the sampler and call i its
/// camera sample i, so a stratified or low-discrepancy sampler stratifies an estimate's calls. Each direction is weighted by the
/// environment's radiance there, whatever side of the surface it is on (so the paper's below-horizon
/// specular directions count with their negative weights, as printed).
FurnaceResult runFurnace(const FurnaceSetup& setup, const Environment& env);

/// A table of furnace runs, as `symphong furnace` makes it: every environment x exponent x view angle x
/// estimator, in that order. Cell k of the table draws from seed mixSeed(seed, k), so cells are
/// independent and a table is reproduced exactly by the same settings, whoever runs it (the command
/// line, the Python module).
struct FurnaceTable {
    std::vector<std::string> estimators = {"symmetric"};
    std::vector<std::string> environments = {"constant"};
    std::vector<double> exponents = {10};
    std::vector<double> thetas = {30};
    double rhoD = 0.3, rhoS = 0.6, phiDeg = 0;
    int repeats = 10000;
    std::uint64_t seed = 1;
    int directions = 16;
    std::string sampler = std::string(kDefaultSampler);
    EstimatorOptions options;
    EnvironmentParams environment;
};

/// The exponents and view angles of `symphong furnace --grid`.
const std::vector<double>& furnaceGridExponents();
const std::vector<double>& furnaceGridThetas();

/// Runs the table's cells in order, calling `onRow` after each. Throws InputError for an unknown
/// estimator, environment or sampler (before running anything). When `cancel` becomes true the table
/// stops after the current cell and the rows so far are returned.
std::vector<FurnaceResult> runFurnaceTable(const FurnaceTable& table, const std::function<void(const FurnaceResult&)>& onRow = {},
                                           const std::atomic<bool>* cancel = nullptr);

/// The rows as the JSON array that `symphong furnace --json` writes (non-finite z and efficiency as null).
std::string furnaceJson(const std::vector<FurnaceResult>& rows);

}  // namespace symphong
