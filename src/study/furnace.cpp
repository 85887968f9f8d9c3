#include "study/furnace.h"

#include "sampling/warp.h"

#include <chrono>
#include <cmath>

namespace symphong {

FurnaceResult runFurnace(const FurnaceSetup& s, const Environment& env) {
    const auto estimator = makeEstimator(s.estimator, s.options);
    PhongMaterial m;
    m.rhoD = Color(s.rhoD);
    m.rhoS = Color(s.rhoS);
    m.exponent = s.n;
    const double deg = kPi / 180.0;
    const Vec3 wo = sphericalDirection(std::cos(s.thetaDeg * deg), s.phiDeg * deg);

    FurnaceResult r;
    r.estimator = s.estimator;
    r.sampler = effectiveSampler(*estimator, s.sampler);
    r.environment = env.name;
    r.rhoD = s.rhoD, r.rhoS = s.rhoS, r.n = s.n, r.thetaDeg = s.thetaDeg;
    r.repeats = s.repeats;
    r.exact = std::isnan(s.knownExact) ? exactReflected(env, s.rhoD, s.rhoS, s.n, wo) : s.knownExact;

    DirectionList out;
    const ShadingContext ctx{wo, &m, 0, true};
    const int calls = estimator->returnsSets() ? 1
                      : estimator->spreadSetSize(ctx) > 1 ? static_cast<int>(estimator->spreadSetSize(ctx))
                                                           : s.directions;
    const auto sampler = makeSampler(r.sampler, static_cast<std::uint32_t>(calls), s.seed);
    double sum = 0, sumSq = 0, directions = 0;
    const auto start = std::chrono::steady_clock::now();
    for (int rep = 0; rep < s.repeats; ++rep) {
        double estimate = 0;
        for (int i = 0; i < calls; ++i) {
            out.clear();
            SampleStream samples(*sampler, static_cast<std::uint64_t>(rep), static_cast<std::uint32_t>(i));
            estimator->sample(ctx, samples, out);
            for (const DirectionSample& d : out) estimate += d.weight.x * env.radiance(d.wi);
            directions += static_cast<double>(out.size());
        }
        estimate /= calls;
        sum += estimate;
        sumSq += estimate * estimate;
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const double M = s.repeats;
    r.estimate = sum / M;
    r.variance = M > 1 ? std::max(0.0, (sumSq - sum * r.estimate) / (M - 1)) : 0.0;
    r.stdError = std::sqrt(r.variance / M);
    r.relativeBias = r.exact != 0 ? (r.estimate - r.exact) / r.exact : 0.0;
    r.z = r.stdError > 0 ? (r.estimate - r.exact) / r.stdError : (std::abs(r.estimate - r.exact) <= 1e-9 * std::abs(r.exact) ? 0.0 : INFINITY);
    r.directionsPerEstimate = directions / M;
    r.varianceTimesDirections = r.variance * r.directionsPerEstimate;
    r.secondsPerEstimate = seconds / M;
    r.efficiency = r.variance > 0 ? 1.0 / (r.variance * r.secondsPerEstimate) : INFINITY;
    return r;
}

}  // namespace symphong
