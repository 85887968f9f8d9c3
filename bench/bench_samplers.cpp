// Directions per second of each warp and each estimator (Google Benchmark). Counters report
// directions/s, so estimators that return several directions per call compare fairly. Estimators draw
// from the independent sampler (a PCG32 generator seeded per value); bench_sampler times the samplers.
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

}  // namespace

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
BENCHMARK_CAPTURE(BM_DiffuseOnly, cosine, std::string("cosine"));
BENCHMARK_CAPTURE(BM_DiffuseOnly, symmetric, std::string("symmetric"));
BENCHMARK_CAPTURE(BM_DiffuseOnly, symmetric_shifted, std::string("symmetric-shifted"));
