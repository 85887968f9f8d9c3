// Directions per second of each warp and each estimator (Google Benchmark). Counters report
// directions/s, so estimators that return several directions per call compare fairly. Estimators draw
// from the independent sampler (a PCG32 generator seeded per value); bench_samplers times the samplers.
#include "estimators/estimator.h"
#include "sampling/warp.h"

#include <benchmark/benchmark.h>

using namespace symphong;

namespace {

template <class Fn>
void warpLoop(benchmark::State& state, Fn&& fn) {
    Rng rng(1, 2);
    for (auto _ : state) benchmark::DoNotOptimize(fn(rng.uniform2()));
    state.counters["directions/s"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}

void BM_UniformHemisphere(benchmark::State& s) { warpLoop(s, sampleUniformHemisphere); }
void BM_CosineHemisphere(benchmark::State& s) { warpLoop(s, sampleCosineHemisphere); }
void BM_PhongLobe(benchmark::State& s) {
    const double n = static_cast<double>(s.range(0));
    warpLoop(s, [n](Point2 p) { return samplePhongLobe(p, n); });
}
void BM_UniformTriangle(benchmark::State& s) { warpLoop(s, sampleUniformTriangle); }

void estimatorLoop(benchmark::State& state, const std::string& name, const PhongMaterial& m) {
    const auto est = makeEstimator(name);
    const ShadingContext ctx{normalize(Vec3(0.3, 0.2, 0.9)), &m, 0, true};
    const IndependentSampler sampler(16, 3);
    DirectionList out;
    std::size_t directions = 0;
    std::uint64_t pixel = 0;
    for (auto _ : state) {
        out.clear();
        SampleStream samples(sampler, pixel++, 3);
        est->sample(ctx, samples, out);
        directions += out.size();
        benchmark::DoNotOptimize(out.data());
    }
    state.counters["directions/s"] = benchmark::Counter(static_cast<double>(directions), benchmark::Counter::kIsRate);
}

/// A glossy material (rho_d 0.3, rho_s 0.6, n 50): the symmetric estimators return 16 + 8 directions.
void BM_Estimator(benchmark::State& state, const std::string& name) {
    PhongMaterial m;
    m.rhoD = Color(0.3);
    m.rhoS = Color(0.6);
    m.exponent = 50;
    estimatorLoop(state, name, m);
}

/// A diffuse material: the symmetric estimators return their 16 pieces, reused by sign flips.
void BM_DiffuseOnly(benchmark::State& state, const std::string& name) {
    PhongMaterial m;
    m.rhoD = Color(0.7);
    estimatorLoop(state, name, m);
}

/// The first hit as the path tracer calls it: one camera sample after another of a 64-spp pixel under the
/// sobol sampler (the default), a glossy material seen at 30 degrees; spread-mode estimators share their
/// round's point, so their cost per call includes the pattern look-ups.
void BM_FirstHit(benchmark::State& state, const std::string& name, SymmetricMode mode, int orbit) {
    PhongMaterial m;
    m.rhoD = Color(0.2);
    m.rhoS = Color(0.7);
    m.exponent = 100;
    EstimatorOptions o;
    o.symmetricMode = mode;
    o.symmetricOrbit = orbit;
    const auto est = makeEstimator(name, o);
    const ShadingContext ctx{normalize(Vec3(0.5, 0.0, 0.866)), &m, 0, true};
    const SobolSampler sampler(64, 3);
    DirectionList out;
    std::size_t directions = 0;
    std::uint64_t i = 0;
    for (auto _ : state) {
        out.clear();
        SampleStream samples(sampler, i / 64, static_cast<std::uint32_t>(i % 64), 1ull << 40);
        ++i;
        est->sample(ctx, samples, out);
        directions += out.size();
        benchmark::DoNotOptimize(out.data());
    }
    state.counters["directions/s"] = benchmark::Counter(static_cast<double>(directions), benchmark::Counter::kIsRate);
}

}  // namespace

BENCHMARK_CAPTURE(BM_FirstHit, phong, std::string("phong"), SymmetricMode::Branch, 8);
BENCHMARK_CAPTURE(BM_FirstHit, symmetric_mix_spread_orbit1, std::string("symmetric-mix"), SymmetricMode::Spread, 1);
BENCHMARK_CAPTURE(BM_FirstHit, symmetric_mix_spread_orbit2, std::string("symmetric-mix"), SymmetricMode::Spread, 2);
BENCHMARK_CAPTURE(BM_FirstHit, symmetric_mix_spread_orbit8, std::string("symmetric-mix"), SymmetricMode::Spread, 8);
BENCHMARK_CAPTURE(BM_FirstHit, symmetric_mix_branch_orbit2, std::string("symmetric-mix"), SymmetricMode::Branch, 2);
BENCHMARK_CAPTURE(BM_FirstHit, symmetric_mix_branch_orbit8, std::string("symmetric-mix"), SymmetricMode::Branch, 8);
BENCHMARK_CAPTURE(BM_FirstHit, symmetric_spread, std::string("symmetric"), SymmetricMode::Spread, 8);
BENCHMARK(BM_UniformHemisphere);
BENCHMARK(BM_CosineHemisphere);
BENCHMARK(BM_PhongLobe)->Arg(10)->Arg(1000);
BENCHMARK(BM_UniformTriangle);
BENCHMARK_CAPTURE(BM_Estimator, uniform, std::string("uniform"));
BENCHMARK_CAPTURE(BM_Estimator, cosine, std::string("cosine"));
BENCHMARK_CAPTURE(BM_Estimator, stratified, std::string("stratified"));
BENCHMARK_CAPTURE(BM_Estimator, phong, std::string("phong"));
BENCHMARK_CAPTURE(BM_Estimator, paper, std::string("paper"));
BENCHMARK_CAPTURE(BM_Estimator, symmetric, std::string("symmetric"));
BENCHMARK_CAPTURE(BM_Estimator, symmetric_shifted, std::string("symmetric-shifted"));
BENCHMARK_CAPTURE(BM_Estimator, symmetric_mix, std::string("symmetric-mix"));
BENCHMARK_CAPTURE(BM_DiffuseOnly, cosine, std::string("cosine"));
BENCHMARK_CAPTURE(BM_DiffuseOnly, symmetric, std::string("symmetric"));
BENCHMARK_CAPTURE(BM_DiffuseOnly, symmetric_shifted, std::string("symmetric-shifted"));
