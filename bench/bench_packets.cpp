// Tracing the 16 diffuse directions of one symmetric estimate from one shading point: 16 single-ray
// queries (Accel::intersect) against the bundle query the path tracer uses (Accel::intersectBundle, one
// 16-wide rtcIntersect16 packet), on the built-in Cornell box.
// Shading points are random points on its floor; counters report rays/s.
#include "accel/accel.h"
#include "estimators/symmetric.h"
#include "math/frame.h"
#include "scene/scene.h"

#include <benchmark/benchmark.h>

#include <array>
#include <limits>

using namespace symphong;

namespace {

struct Batch {
    std::vector<Vec3> origins;
    std::vector<std::array<Vec3, 16>> dirs;
};

const Scene& cornell() {
    static const Scene s = [] {
        Scene c = makeCornellBox();
        finalizeScene(c, "cornell", false);
        return c;
    }();
    return s;
}

Batch makeBatch(std::size_t points) {
    Batch b;
    const SymmetricEstimator est(1, false);
    PhongMaterial m;
    Rng rng(5, 6);
    const IndependentSampler sampler(1, 7);
    DirectionList out;
    for (std::size_t i = 0; i < points; ++i) {
        b.origins.push_back(Vec3(50 + 450 * rng.uniform(), 1e-2, 50 + 450 * rng.uniform()));
        out.clear();
        SampleStream samples(sampler, i, 0);
        est.sample(ShadingContext{Vec3(0, 0, 1), &m, 0, true}, samples, out);
        const Frame f = Frame::fromNormal(Vec3(0, 1, 0));
        std::array<Vec3, 16> d{};
        for (int k = 0; k < 16; ++k) d[k] = f.toWorld(out[k].wi);
        b.dirs.push_back(d);
    }
    return b;
}

void BM_Single16(benchmark::State& state) {
    const Accel accel(cornell());
    const Batch b = makeBatch(4096);
    std::size_t i = 0, rays = 0;
    for (auto _ : state) {
        const std::size_t p = i++ % b.origins.size();
        for (int k = 0; k < 16; ++k) {
            Hit h;
            benchmark::DoNotOptimize(accel.intersect(b.origins[p], b.dirs[p][k], 0.0, std::numeric_limits<double>::infinity(), h));
        }
        rays += 16;
    }
    state.counters["rays/s"] = benchmark::Counter(static_cast<double>(rays), benchmark::Counter::kIsRate);
}

// The path tracer's own bundle query (Accel::intersectBundle: one 16-wide rtcIntersect16 packet).
void BM_Bundle16(benchmark::State& state) {
    const Accel accel(cornell());
    const Batch b = makeBatch(4096);
    std::size_t i = 0, rays = 0;
    std::array<Hit, 16> hits;
    bool found[16];
    for (auto _ : state) {
        const std::size_t p = i++ % b.origins.size();
        accel.intersectBundle(b.origins[p], b.dirs[p].data(), 16, 0.0, hits.data(), found);
        benchmark::DoNotOptimize(found[0]);
        rays += 16;
    }
    state.counters["rays/s"] = benchmark::Counter(static_cast<double>(rays), benchmark::Counter::kIsRate);
}

}  // namespace

BENCHMARK(BM_Single16);
BENCHMARK(BM_Bundle16);
