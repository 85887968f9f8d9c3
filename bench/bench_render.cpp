// End-to-end render benchmark: renders the built-in Cornell box and a large mesh (the Stanford bunny
// from the shared scenes) and prints Mrays/s and samples/s, next to Embree's raw incoherent ray rate
// on the same scene (random rays through the bounding box, rtcIntersect1, no shading) and our rate as
// a fraction of it. Not a test: numbers go to docs/performance.md.
#include "accel/accel.h"
#include "estimators/estimator.h"
#include "render/renderer.h"
#include "sampling/warp.h"
#include "scene/scene.h"

#include <embree3/rtcore.h>
#include <fmt/format.h>
#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_arena.h>
#include <CLI/CLI.hpp>

#include <chrono>
#include <filesystem>
#include <thread>

using namespace symphong;

namespace {

/// Rays per second of rtcIntersect1 on random rays: origins uniform in the bounding box, directions
/// uniform on the sphere (the most incoherent workload there is). The rays are generated before the
/// clock starts, so only Embree's traversal is timed.
double rawEmbreeRate(const Scene& scene, const Accel& accel, int threads) {
    Vec3 lo, hi;
    scene.bounds(lo, hi);
    constexpr std::size_t kRays = 1u << 20;
    constexpr int kPasses = 4;
    std::vector<RTCRayHit> rays(kRays);
    Rng rng(12345, 17);
    for (RTCRayHit& rh : rays) {
        const Vec3 o = lo + (hi - lo) * Vec3(rng.uniform(), rng.uniform(), rng.uniform());
        Vec3 d = sampleUniformHemisphere(rng.uniform2());
        if (rng.uniform() < 0.5) d.z = -d.z;
        rh = RTCRayHit{};
        rh.ray.org_x = static_cast<float>(o.x), rh.ray.org_y = static_cast<float>(o.y), rh.ray.org_z = static_cast<float>(o.z);
        rh.ray.dir_x = static_cast<float>(d.x), rh.ray.dir_y = static_cast<float>(d.y), rh.ray.dir_z = static_cast<float>(d.z);
        rh.ray.mask = 0xFFFFFFFFu;
    }
    tbb::task_arena arena(threads);
    const auto start = std::chrono::steady_clock::now();
    for (int pass = 0; pass < kPasses; ++pass) {
        arena.execute([&] {
            tbb::parallel_for(tbb::blocked_range<std::size_t>(0, kRays, 4096), [&](const tbb::blocked_range<std::size_t>& r) {
                RTCIntersectContext ctx;
                rtcInitIntersectContext(&ctx);
                for (std::size_t i = r.begin(); i != r.end(); ++i) {
                    RTCRayHit& rh = rays[i];
                    rh.ray.tnear = 0;
                    rh.ray.tfar = std::numeric_limits<float>::infinity();
                    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
                    rtcIntersect1(accel.handle(), &ctx, &rh);
                }
            });
        });
    }
    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return static_cast<double>(kRays) * kPasses / secs;
}

void benchScene(const std::string& spec, const std::string& estimatorName, int size, std::uint32_t spp, int threads) {
    const Scene scene = loadScene(spec);
    const Accel accel(scene);
    const auto estimator = makeEstimator(estimatorName);
    RenderSettings rs;
    rs.width = rs.height = size;
    rs.spp = spp;
    rs.threads = threads;
    render(scene, accel, *estimator, rs);  // warm-up
    const RenderResult r = render(scene, accel, *estimator, rs);
    const double raysPerSec = r.stats.rays / r.stats.seconds;
    const double raw = rawEmbreeRate(scene, accel, threads);
    fmt::print(
        "{:<22} {:>9} tris  {:<10} {}x{} {:>4} spp  {:6.2f} s  {:7.2f} Mrays/s  {:7.3f} Msamples/s  | raw Embree {:7.2f} Mrays/s  ratio "
        "{:.2f}\n",
        scene.name, scene.triangles.size(), estimatorName, size, size, spp, r.stats.seconds, raysPerSec / 1e6,
        r.stats.samples / r.stats.seconds / 1e6, raw / 1e6, raysPerSec / raw);
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"symphong end-to-end render benchmark"};
    int threads = static_cast<int>(std::thread::hardware_concurrency());
    int size = 256;
    std::uint32_t spp = 16;
    std::string bunny = std::string(SYMPHONG_SHARED_SCENES) + "/bunny/stanford-bunny.obj";
    std::vector<std::string> estimators = {"phong"};
    app.add_option("--threads", threads, "worker threads")->capture_default_str();
    app.add_option("--size", size, "image width and height")->capture_default_str();
    app.add_option("--spp", spp, "samples per pixel")->capture_default_str();
    app.add_option("--mesh", bunny, "large OBJ mesh to benchmark")->capture_default_str();
    app.add_option("--estimators", estimators, "estimators to time")->delimiter(',')->capture_default_str();
    CLI11_PARSE(app, argc, argv);
    fmt::print("threads: {}\n", threads);
    for (const auto& e : estimators) benchScene("cornell", e, size, spp, threads);
    if (std::filesystem::exists(bunny)) {
        for (const auto& e : estimators) benchScene(bunny, e, size, spp, threads);
    } else {
        fmt::print(stderr, "bench_render: {} not found; skipping the large mesh\n", bunny);
    }
    return 0;
}
