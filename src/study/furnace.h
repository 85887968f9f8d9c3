// study/furnace.h — the single-point furnace: one shading point, one material, one environment with an
// exact answer, M independent estimates. Measures bias (with its z-score), the variance of one estimate,
// the variance per direction (equal-direction comparison) and the time per estimate.
#pragma once

#include "estimators/estimator.h"
#include "study/environment.h"

#include <cstdint>
#include <limits>
#include <string>

namespace symphong {

struct FurnaceSetup {
    std::string estimator = "symmetric";
    EstimatorOptions options;
    double rhoD = 0.3, rhoS = 0.6, n = 10, thetaDeg = 30;  ///< grey material and view angle from the normal
    double phiDeg = 0;        ///< view azimuth
    int repeats = 10000;      ///< M independent estimates
    std::uint64_t seed = 1;
    int directions = 16;      ///< estimators that return one direction per call are called this many times per estimate
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
    double variance = 0;             ///< variance of one estimate
    double directionsPerEstimate = 0;
    double varianceTimesDirections = 0;  ///< per-direction variance: compares estimators at equal directions
    double secondsPerEstimate = 0;
    double efficiency = 0;           ///< 1 / (variance * seconds per estimate)
};

/// Runs M estimates. One estimate is one call of a set-returning estimator (paper, symmetric: its whole
/// set of directions), the mean of one whole spread set's calls (spread mode: P N' calls), or the mean of
/// `directions` calls of a one-direction estimator. Estimate r is pixel r of the sampler and call i its
/// camera sample i, so a stratified or low-discrepancy sampler stratifies an estimate's calls. Each direction is weighted by the
/// environment's radiance there, whatever side of the surface it is on (so the paper's below-horizon
/// specular directions count with their negative weights, as printed).
FurnaceResult runFurnace(const FurnaceSetup& setup, const Environment& env);

}  // namespace symphong
