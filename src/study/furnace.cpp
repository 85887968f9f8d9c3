#include "study/furnace.h"

#include "io/input_error.h"
#include "sampling/rng.h"
#include "sampling/sampler.h"
#include "sampling/warp.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <stdexcept>

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
    const int calls = estimator->returnsSets()            ? 1
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
    r.z = r.stdError > 0 ? (r.estimate - r.exact) / r.stdError
                         : (std::abs(r.estimate - r.exact) <= 1e-9 * std::abs(r.exact) ? 0.0 : INFINITY);
    r.directionsPerEstimate = directions / M;
    r.varianceTimesDirections = r.variance * r.directionsPerEstimate;
    r.secondsPerEstimate = seconds / M;
    r.efficiency = r.variance > 0 ? 1.0 / (r.variance * r.secondsPerEstimate) : INFINITY;
    return r;
}

const std::vector<double>& furnaceGridExponents() {
    static const std::vector<double> values{1, 10, 100, 1000, 10000};
    return values;
}

const std::vector<double>& furnaceGridThetas() {
    static const std::vector<double> values{0, 30, 60, 85};
    return values;
}

std::vector<FurnaceResult> runFurnaceTable(const FurnaceTable& t, const std::function<void(const FurnaceResult&)>& onRow,
                                           const std::atomic<bool>* cancel) {
    // Every value and name is checked before the first cell runs, so bad input never costs a partial table.
    const auto require = [](bool ok, const std::string& message) {
        if (!ok) throw InputError(message);
    };
    require(t.rhoD >= 0 && t.rhoD <= 1, fmt::format("rho_d = {} must lie in [0, 1]", t.rhoD));
    require(t.rhoS >= 0 && t.rhoS <= 1, fmt::format("rho_s = {} must lie in [0, 1]", t.rhoS));
    require(std::isfinite(t.phiDeg), fmt::format("phi = {} is not finite", t.phiDeg));
    require(t.repeats >= 2, fmt::format("repeats = {} must be at least 2 (the variance needs two estimates)", t.repeats));
    require(t.directions >= 1, fmt::format("directions = {} must be at least 1", t.directions));
    require(!t.estimators.empty() && !t.environments.empty() && !t.exponents.empty() && !t.thetas.empty(),
            "the furnace table needs at least one estimator, environment, exponent and view angle");
    for (double n : t.exponents) require(n >= 0 && std::isfinite(n), fmt::format("n = {} must be a finite exponent >= 0", n));
    for (double theta : t.thetas)
        require(theta >= 0 && theta < 90,
                fmt::format("theta = {} must lie in [0, 90) degrees (the view must be above the surface)", theta));
    for (const std::string& e : t.estimators) {
        try {
            makeEstimator(e, t.options);
        } catch (const std::invalid_argument& err) {
            throw InputError(fmt::format("estimator: {}", err.what()));
        }
    }
    try {
        makeSampler(t.sampler, 1, 1);
    } catch (const std::invalid_argument& err) {
        throw InputError(fmt::format("sampler: {}", err.what()));
    }
    std::vector<Environment> environments;
    for (const std::string& name : t.environments) {
        try {
            environments.push_back(makeEnvironment(name, t.environment));
        } catch (const std::invalid_argument& err) {
            throw InputError(fmt::format("environment: {}", err.what()));
        }
    }
    std::vector<FurnaceResult> rows;
    std::uint64_t cell = 0;
    for (const Environment& env : environments)
        for (double n : t.exponents)
            for (double theta : t.thetas)
                for (const std::string& est : t.estimators) {
                    if (cancel && cancel->load()) return rows;
                    FurnaceSetup setup;
                    setup.estimator = est;
                    setup.options = t.options;
                    setup.rhoD = t.rhoD, setup.rhoS = t.rhoS, setup.n = n, setup.thetaDeg = theta, setup.phiDeg = t.phiDeg;
                    setup.repeats = t.repeats, setup.seed = mixSeed(t.seed, cell++), setup.directions = t.directions;
                    setup.sampler = t.sampler;
                    rows.push_back(runFurnace(setup, env));
                    if (onRow) onRow(rows.back());
                }
    return rows;
}

std::string furnaceJson(const std::vector<FurnaceResult>& rows) {
    const auto finiteOrNull = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); };
    nlohmann::json out = nlohmann::json::array();
    for (const FurnaceResult& r : rows)
        out.push_back({{"estimator", r.estimator},
                       {"sampler", r.sampler},
                       {"environment", r.environment},
                       {"rho_d", r.rhoD},
                       {"rho_s", r.rhoS},
                       {"n", r.n},
                       {"theta_deg", r.thetaDeg},
                       {"repeats", r.repeats},
                       {"estimate", r.estimate},
                       {"std_error", r.stdError},
                       {"exact", r.exact},
                       {"relative_bias", r.relativeBias},
                       {"z", finiteOrNull(r.z)},
                       {"variance", r.variance},
                       {"directions_per_estimate", r.directionsPerEstimate},
                       {"variance_times_directions", r.varianceTimesDirections},
                       {"seconds_per_estimate", r.secondsPerEstimate},
                       {"efficiency", finiteOrNull(r.efficiency)}});
    return out.dump(2) + "\n";
}

}  // namespace symphong
