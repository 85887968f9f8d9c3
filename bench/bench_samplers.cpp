// Samplers: nanoseconds per value of each sampler (1D and 2D), the cost a sampler adds to a render, and
// of the low-discrepancy building blocks alone. The samplers are made by makeSampler and called through
// the Sampler interface (a virtual call, as the renderer does). spp = 64; every iteration asks for
// another (pixel, sample index, dimension), so nothing can be hoisted out of the loop:
//   Sample1D / Sample2D — sampler.sample1D/sample2D(pixel, index, dim): includes hashing (seed, pixel);
//   Value1D / Value2D   — sampler.value1D/value2D(key, index, spp, dim) with the pixel key hashed once per
//                         pixel, as SampleStream (what estimators and the path tracer draw from) does.
//   PairsOfSixteenPaths — SobolSampler::pairValue of 16 paths (16 pixels, the same sample and dimension): one
//                         call a path, as the path tracer asks, against one loop over the 16 (a wavefront's
//                         sampler stage written plainly, what the compiler makes of it; _avx2 with AVX2 allowed;
//                         _Lanes: sobol_lanes.h's vector lanes, the wavefront tracer's, where the CPU has them).
#include "sampling/lowdiscrepancy.h"
#include "sampling/sampler.h"
#include "sampling/sobol_lanes.h"

#include <benchmark/benchmark.h>

#include <cstdint>
#include <string>

using namespace symphong;

namespace {

constexpr std::uint32_t kSpp = 64;

// Iteration k asks for sample k mod 64, dimension (k / 64) mod 32 (times 2 for pairs), pixel k / 2048.
inline std::uint32_t indexOf(std::uint64_t k) { return static_cast<std::uint32_t>(k & (kSpp - 1)); }
inline std::uint64_t dimOf(std::uint64_t k) { return (k >> 6) & 31; }
inline std::uint64_t pixelOf(std::uint64_t k) { return k >> 11; }

void BM_Sample1D(benchmark::State& state, const std::string& name) {
    const auto sampler = makeSampler(name, kSpp, 7);
    std::uint64_t k = 0;
    for (auto _ : state) {
        benchmark::DoNotOptimize(sampler->sample1D(pixelOf(k), indexOf(k), dimOf(k)));
        ++k;
    }
    state.SetItemsProcessed(state.iterations());
}

void BM_Sample2D(benchmark::State& state, const std::string& name) {
    const auto sampler = makeSampler(name, kSpp, 7);
    std::uint64_t k = 0;
    for (auto _ : state) {
        const Point2 p = sampler->sample2D(pixelOf(k), indexOf(k), 2 * dimOf(k));
        benchmark::DoNotOptimize(p.u);
        benchmark::DoNotOptimize(p.v);
        ++k;
    }
    state.SetItemsProcessed(state.iterations());
}

void BM_Value1D(benchmark::State& state, const std::string& name) {
    const auto sampler = makeSampler(name, kSpp, 7);
    std::uint64_t k = 0, key = sampler->pixelKey(0);
    for (auto _ : state) {
        benchmark::DoNotOptimize(sampler->value1D(key, indexOf(k), kSpp, dimOf(k)));
        if ((++k & 2047) == 0) key = sampler->pixelKey(pixelOf(k));
    }
    state.SetItemsProcessed(state.iterations());
}

void BM_Value2D(benchmark::State& state, const std::string& name) {
    const auto sampler = makeSampler(name, kSpp, 7);
    std::uint64_t k = 0, key = sampler->pixelKey(0);
    for (auto _ : state) {
        const Point2 p = sampler->value2D(key, indexOf(k), kSpp, 2 * dimOf(k));
        benchmark::DoNotOptimize(p.u);
        benchmark::DoNotOptimize(p.v);
        if ((++k & 2047) == 0) key = sampler->pixelKey(pixelOf(k));
    }
    state.SetItemsProcessed(state.iterations());
}

// Building blocks: throughput of independent calls on varying inputs.
void BM_OwenScramble(benchmark::State& state) {
    std::uint32_t k = 0;
    for (auto _ : state) {
        benchmark::DoNotOptimize(owenScramble(k * 0x9E3779B9u, k ^ 0x5bd1e995u));
        ++k;
    }
    state.SetItemsProcessed(state.iterations());
}

void BM_OwenScrambleExact(benchmark::State& state) {
    std::uint32_t k = 0;
    for (auto _ : state) {
        benchmark::DoNotOptimize(owenScrambleExact(k * 0x9E3779B9u, k ^ 0x5bd1e995u));
        ++k;
    }
    state.SetItemsProcessed(state.iterations());
}

// sobolDimension1 (four table look-ups) and sobolDimension1Loop (a loop over the index's set bits): on
// indices below spp = 64 in a scrambled order (what the samplers ask for; the loop's branches are then
// unpredictable) and on full 32-bit indices.
inline std::uint32_t scrambledBelow64(std::uint32_t k) { return hash32(k) & 63u; }

void BM_SobolDimension1_Below64(benchmark::State& state) {
    std::uint32_t k = 0;
    for (auto _ : state) {
        benchmark::DoNotOptimize(sobolDimension1(scrambledBelow64(k)));
        ++k;
    }
    state.SetItemsProcessed(state.iterations());
}

void BM_SobolDimension1_Full32(benchmark::State& state) {
    std::uint32_t k = 0;
    for (auto _ : state) {
        benchmark::DoNotOptimize(sobolDimension1(k * 0x9E3779B9u));
        ++k;
    }
    state.SetItemsProcessed(state.iterations());
}

void BM_SobolDimension1Loop_Below64(benchmark::State& state) {
    std::uint32_t k = 0;
    for (auto _ : state) {
        benchmark::DoNotOptimize(sobolDimension1Loop(scrambledBelow64(k)));
        ++k;
    }
    state.SetItemsProcessed(state.iterations());
}

void BM_SobolDimension1Loop_Full32(benchmark::State& state) {
    std::uint32_t k = 0;
    for (auto _ : state) {
        benchmark::DoNotOptimize(sobolDimension1Loop(k * 0x9E3779B9u));
        ++k;
    }
    state.SetItemsProcessed(state.iterations());
}

// The hash32 of the input alone, to subtract from the Below64 rows.
void BM_Hash32(benchmark::State& state) {
    std::uint32_t k = 0;
    for (auto _ : state) {
        benchmark::DoNotOptimize(scrambledBelow64(k));
        ++k;
    }
    state.SetItemsProcessed(state.iterations());
}

void BM_PermuteIndex(benchmark::State& state) {
    const auto n = static_cast<std::uint32_t>(state.range(0));
    std::uint32_t k = 0;
    for (auto _ : state) {
        benchmark::DoNotOptimize(permuteIndex(k % n, n, hash32(k / n)));
        ++k;
    }
    state.SetItemsProcessed(state.iterations());
}

void BM_PermutePowerOfTwo(benchmark::State& state) {
    const auto log2n = static_cast<std::uint32_t>(state.range(0));
    const std::uint32_t mask = (1u << log2n) - 1u;
    std::uint32_t k = 0;
    for (auto _ : state) {
        benchmark::DoNotOptimize(permutePowerOfTwo(k & mask, log2n, hash32(k >> log2n)));
        ++k;
    }
    state.SetItemsProcessed(state.iterations());
}

// The pairs of 16 paths: pixel keys of 16 pixels, sample k mod 64, dimension (k / 64) mod 32 times 2.
struct SixteenPaths {
    std::uint64_t key[16];
    std::uint32_t index[16];
    double u[16], v[16];
    explicit SixteenPaths(std::uint64_t k) {
        for (int i = 0; i < 16; ++i) {
            key[i] = (pixelOf(k) * 16 + static_cast<std::uint64_t>(i)) * 0x9E3779B97F4A7C15ull;  // cheap: the pairs are measured
            index[i] = indexOf(k);
        }
    }
};

// The loop, inlined into each of the two targets below (compiled for each).
[[gnu::always_inline]] inline void pairsLoop(SixteenPaths& p, std::uint64_t dim) {
    for (int i = 0; i < 16; ++i) {
        const Point2 q = SobolSampler::pairValue(p.key[i], p.index[i], kSpp, dim);
        p.u[i] = q.u;
        p.v[i] = q.v;
    }
}

[[gnu::noinline]] void pairsInOneLoop(SixteenPaths& p, std::uint64_t dim) { pairsLoop(p, dim); }
[[gnu::noinline, gnu::target("avx2,bmi2")]] void pairsInOneLoopAvx2(SixteenPaths& p, std::uint64_t dim) { pairsLoop(p, dim); }

[[gnu::noinline]] void pairsInLanes(SixteenPaths& p, std::uint64_t dim) {
    detail::sobolPairValuesLanes(p.key, p.index, kSpp, dim, 16, p.u, p.v);
}

void BM_PairsOfSixteenPaths_OneCallAPath(benchmark::State& state) {
    std::uint64_t k = 0;
    for (auto _ : state) {
        SixteenPaths p(k);
        for (int i = 0; i < 16; ++i) {
            const Point2 q = SobolSampler::pairValue(p.key[i], p.index[i], kSpp, 2 * dimOf(k));
            benchmark::DoNotOptimize(q);
        }
        ++k;
    }
    state.SetItemsProcessed(state.iterations() * 16);
}

template <void (*Loop)(SixteenPaths&, std::uint64_t)>
void BM_PairsOfSixteenPaths_OneLoop(benchmark::State& state) {
    // The loop's values are the calls' (checked once: a benchmark of other values would measure nothing).
    SixteenPaths check(12345);
    Loop(check, 6);
    for (int i = 0; i < 16; ++i)
        if (Point2 q = SobolSampler::pairValue(check.key[i], check.index[i], kSpp, 6); q.u != check.u[i] || q.v != check.v[i]) {
            state.SkipWithError("the loop's values differ from pairValue's");
            return;
        }
    std::uint64_t k = 0;
    for (auto _ : state) {
        SixteenPaths p(k);
        Loop(p, 2 * dimOf(k));
        benchmark::DoNotOptimize(p.u);
        benchmark::DoNotOptimize(p.v);
        ++k;
    }
    state.SetItemsProcessed(state.iterations() * 16);
}

void BM_PairsOfSixteenPaths_OneLoop_avx2(benchmark::State& state) {
    if (!__builtin_cpu_supports("avx2") || !__builtin_cpu_supports("bmi2")) {
        state.SkipWithError("this CPU has no AVX2");
        return;
    }
    BM_PairsOfSixteenPaths_OneLoop<pairsInOneLoopAvx2>(state);
}

void BM_PairsOfSixteenPaths_Lanes(benchmark::State& state) {
    if (!sobolLanesAvailable()) {
        state.SkipWithError("this CPU has no AVX-512 and GFNI");
        return;
    }
    BM_PairsOfSixteenPaths_OneLoop<pairsInLanes>(state);
}

}  // namespace

BENCHMARK_CAPTURE(BM_Sample1D, independent, std::string("independent"));
BENCHMARK_CAPTURE(BM_Sample1D, stratified, std::string("stratified"));
BENCHMARK_CAPTURE(BM_Sample1D, sobol, std::string("sobol"));
BENCHMARK_CAPTURE(BM_Sample2D, independent, std::string("independent"));
BENCHMARK_CAPTURE(BM_Sample2D, stratified, std::string("stratified"));
BENCHMARK_CAPTURE(BM_Sample2D, sobol, std::string("sobol"));
BENCHMARK_CAPTURE(BM_Value1D, independent, std::string("independent"));
BENCHMARK_CAPTURE(BM_Value1D, stratified, std::string("stratified"));
BENCHMARK_CAPTURE(BM_Value1D, sobol, std::string("sobol"));
BENCHMARK_CAPTURE(BM_Value2D, independent, std::string("independent"));
BENCHMARK_CAPTURE(BM_Value2D, stratified, std::string("stratified"));
BENCHMARK_CAPTURE(BM_Value2D, sobol, std::string("sobol"));
BENCHMARK(BM_OwenScramble);
BENCHMARK(BM_OwenScrambleExact);
BENCHMARK(BM_SobolDimension1_Below64);
BENCHMARK(BM_SobolDimension1_Full32);
BENCHMARK(BM_SobolDimension1Loop_Below64);
BENCHMARK(BM_SobolDimension1Loop_Full32);
BENCHMARK(BM_Hash32);
BENCHMARK(BM_PermuteIndex)->Arg(64)->Arg(100);
BENCHMARK(BM_PermutePowerOfTwo)->Arg(6);
BENCHMARK(BM_PairsOfSixteenPaths_OneCallAPath);
BENCHMARK(BM_PairsOfSixteenPaths_OneLoop<pairsInOneLoop>)->Name("BM_PairsOfSixteenPaths_OneLoop");
BENCHMARK(BM_PairsOfSixteenPaths_OneLoop_avx2);
BENCHMARK(BM_PairsOfSixteenPaths_Lanes);
