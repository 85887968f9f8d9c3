// FLIP and HDR-FLIP (compare/flip.h) on a pair of images of each size: what `symphong compare` spends on
// its perceptual error, and what a study's report.html spends per render (one HDR-FLIP each).
// The pair: a smooth HDR image with a bright disc (a light) and the same with per-pixel noise.
#include "compare/flip.h"

#include <benchmark/benchmark.h>

#include <random>

namespace {

using symphong::Color;
using symphong::Image;

std::pair<Image, Image> pair(int size) {
    Image ref(size, size), test(size, size);
    std::mt19937 rng(1);
    std::normal_distribution<double> noise(0.0, 0.2);
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            const double u = (x + 0.5) / size, v = (y + 0.5) / size;
            const double light = (u - 0.5) * (u - 0.5) + (v - 0.15) * (v - 0.15) < 0.005 ? 40.0 : 0.0;
            const Color c{0.05 + 0.6 * u + light, 0.05 + 0.4 * v + light, 0.1 + 0.2 * u * v + light};
            ref.at(x, y) = c;
            const double n = 1 + noise(rng);
            test.at(x, y) = c * (n > 0 ? n : 0.0);
        }
    return {ref, test};
}

void HdrFlip(benchmark::State& state) {
    const auto [ref, test] = pair(static_cast<int>(state.range(0)));
    for (auto _ : state) benchmark::DoNotOptimize(symphong::hdrFlip(ref, test).mean);
    state.SetItemsProcessed(state.iterations() * state.range(0) * state.range(0));
}
BENCHMARK(HdrFlip)->Arg(128)->Arg(512)->Unit(benchmark::kMillisecond);

void LdrFlip(benchmark::State& state) {
    auto [ref, test] = pair(static_cast<int>(state.range(0)));
    for (Image* img : {&ref, &test})
        for (Color& c : img->pixels) c = Color{std::min(c.x, 1.0), std::min(c.y, 1.0), std::min(c.z, 1.0)};
    for (auto _ : state) benchmark::DoNotOptimize(symphong::ldrFlip(ref, test).mean);
    state.SetItemsProcessed(state.iterations() * state.range(0) * state.range(0));
}
BENCHMARK(LdrFlip)->Arg(128)->Arg(512)->Unit(benchmark::kMillisecond);

}  // namespace
