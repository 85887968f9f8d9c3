#include <benchmark/benchmark.h>
static void BM_Placeholder(benchmark::State& s) { for (auto _ : s) benchmark::DoNotOptimize(s.iterations()); }
BENCHMARK(BM_Placeholder);
