// Tracing the 16 diffuse directions of one symmetric estimate from one shading point: 16 single-ray
// queries (rtcIntersect1) against one 16-wide packet (rtcIntersect16), on the built-in Cornell box.
// Shading points are random points on its floor; counters report rays/s.
#include "accel/accel.h"
#include "estimators/symmetric.h"
#include "math/frame.h"
#include "scene/scene.h"

#include <benchmark/benchmark.h>
#include <embree3/rtcore.h>

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
    std::vector<DirectionSample> out;
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

void BM_Packet16(benchmark::State& state) {
    const Accel accel(cornell());
    const Batch b = makeBatch(4096);
    std::size_t i = 0, rays = 0;
    alignas(64) int valid[16];
    for (int& v : valid) v = -1;
    for (auto _ : state) {
        const std::size_t p = i++ % b.origins.size();
        alignas(64) RTCRayHit16 rh;
        for (int k = 0; k < 16; ++k) {
            rh.ray.org_x[k] = static_cast<float>(b.origins[p].x);
            rh.ray.org_y[k] = static_cast<float>(b.origins[p].y);
            rh.ray.org_z[k] = static_cast<float>(b.origins[p].z);
            rh.ray.dir_x[k] = static_cast<float>(b.dirs[p][k].x);
            rh.ray.dir_y[k] = static_cast<float>(b.dirs[p][k].y);
            rh.ray.dir_z[k] = static_cast<float>(b.dirs[p][k].z);
            rh.ray.tnear[k] = 0;
            rh.ray.tfar[k] = std::numeric_limits<float>::infinity();
            rh.ray.time[k] = 0;
            rh.ray.mask[k] = 0xFFFFFFFFu;
            rh.ray.id[k] = static_cast<unsigned>(k);
            rh.ray.flags[k] = 0;
            rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
        }
        RTCIntersectContext ctx;
        rtcInitIntersectContext(&ctx);
        ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
        rtcIntersect16(valid, accel.handle(), &ctx, &rh);
        benchmark::DoNotOptimize(rh.hit.geomID[0]);
        rays += 16;
    }
    state.counters["rays/s"] = benchmark::Counter(static_cast<double>(rays), benchmark::Counter::kIsRate);
}

}  // namespace

BENCHMARK(BM_Single16);
BENCHMARK(BM_Packet16);
