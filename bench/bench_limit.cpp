// The limit of a render's speed: the render's own rays traced by Embree alone. A scene is rendered once
// with one thread while Accel records every query (camera rays, then each path's bounce and shadow rays,
// in the order the render asked for them), then the same render is timed with all threads, then the
// recorded rays are traced again by rtcIntersect1 / rtcOccluded1 alone, in their order, in chunks of
// 4096 over the same threads: no sampling, shading or bookkeeping. "ratio" is the renderer's rays/s over
// Embree's on those same rays: the share of the time the renderer leaves to Embree. The replay runs twice:
// ray by ray, and in 16-wide packets of each chunk's closest-hit and shadow queries (the faster limit,
// now that the wavefront gives Embree its rays in packets). Not a test: numbers go to docs/performance.md
// ("The limit").
//   bench_limit [--scenes cornell,scenes/cornell-glossy-100.json,scenes/textured.json,sphere2m]
//               [--size 256] [--spp 16] [--threads N] [--estimator phong] [--split K] [--repeats 3] [--tracer automatic|recursive|wavefront]
// --tracer: which tracer takes the camera samples (TraceSettings::tracer; automatic: the wavefront where the
// sampler's vector lanes run).
// "sphere2m" is the built-in Cornell box with a 2,000,000-triangle sphere on its floor (made here).
#include "accel/accel.h"
#include "estimators/estimator.h"
#include "render/renderer.h"
#include "scene/scene.h"

#include <embree3/rtcore.h>
#include <fmt/format.h>
#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_arena.h>
#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <thread>

using namespace symphong;

namespace {

/// The Cornell box with a UV sphere of 2 x 1000 x 999 = 1,998,000 triangles (plus its 32) resting on the
/// floor in front of the blocks, in the tall block's glossy material.
Scene sphereInCornellBox() {
    Scene s = makeCornellBox();
    s.name = "sphere2m";
    const int nu = 1000, nv = 1000;
    const Vec3 c(278, 100, 150);
    const double r = 100;
    const auto base = static_cast<std::uint32_t>(s.positions.size());
    for (int j = 0; j <= nv; ++j)
        for (int i = 0; i < nu; ++i) {
            const double theta = kPi * j / nv, phi = kTwoPi * i / nu;
            s.positions.push_back(c + Vec3(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi)) * r);
        }
    const auto at = [&](int i, int j) { return base + static_cast<std::uint32_t>(j * nu + (i % nu)); };
    const auto material = static_cast<std::uint32_t>(s.findMaterial("tallBlock"));
    for (int j = 0; j < nv; ++j)
        for (int i = 0; i < nu; ++i) {
            Triangle a, b;
            a.v = {at(i, j), at(i + 1, j), at(i + 1, j + 1)};
            b.v = {at(i, j), at(i + 1, j + 1), at(i, j + 1)};
            a.material = b.material = material;
            if (j != 0) s.triangles.push_back(a);  // the rows at the poles: one triangle per quad
            if (j != nv - 1) s.triangles.push_back(b);
        }
    return s;
}

/// Rays per second of Embree alone on the recorded queries, in their order, chunks of 4096 over
/// `threads` threads; the median of `repeats` passes. One by one (rtcIntersect1 / rtcOccluded1), or
/// `packets`: each chunk's closest-hit queries, then its shadow queries, 16 a packet in their order
/// (rtcIntersect16 / rtcOccluded16), as the wavefront gives a depth's rays to Embree.
double replayRate(const Accel& accel, const std::vector<RayQuery>& rays, int threads, int repeats, bool packets) {
    tbb::task_arena arena(threads);
    std::vector<double> rates;
    for (int pass = 0; pass < repeats; ++pass) {
        const auto start = std::chrono::steady_clock::now();
        arena.execute([&] {
            tbb::parallel_for(tbb::blocked_range<std::size_t>(0, rays.size(), 4096), [&](const tbb::blocked_range<std::size_t>& range) {
                RTCIntersectContext ctx;
                rtcInitIntersectContext(&ctx);
                if (packets) {
                    // The chunk's closest-hit queries, then its shadow queries, 16 a packet in their order.
                    for (int shadow = 0; shadow < 2; ++shadow) {
                        alignas(64) RTCRayHit16 rh;
                        alignas(64) int valid[16];
                        std::size_t lane = 0;
                        const auto flush = [&] {
                            for (std::size_t k = 0; k < 16; ++k) valid[k] = k < lane ? -1 : 0;
                            if (shadow)
                                rtcOccluded16(valid, accel.handle(), &ctx, &rh.ray);
                            else
                                rtcIntersect16(valid, accel.handle(), &ctx, &rh);
                            lane = 0;
                        };
                        for (std::size_t i = range.begin(); i != range.end(); ++i) {
                            const RayQuery& q = rays[i];
                            if (q.shadow != (shadow == 1)) continue;
                            rh.ray.org_x[lane] = q.org[0], rh.ray.org_y[lane] = q.org[1], rh.ray.org_z[lane] = q.org[2];
                            rh.ray.dir_x[lane] = q.dir[0], rh.ray.dir_y[lane] = q.dir[1], rh.ray.dir_z[lane] = q.dir[2];
                            rh.ray.tnear[lane] = q.tnear, rh.ray.tfar[lane] = q.tfar;
                            rh.ray.time[lane] = 0, rh.ray.mask[lane] = 0xFFFFFFFFu, rh.ray.id[lane] = 0, rh.ray.flags[lane] = 0;
                            rh.hit.geomID[lane] = RTC_INVALID_GEOMETRY_ID;
                            rh.hit.instID[0][lane] = RTC_INVALID_GEOMETRY_ID;
                            if (++lane == 16) flush();
                        }
                        if (lane > 0) flush();
                    }
                    return;
                }
                for (std::size_t i = range.begin(); i != range.end(); ++i) {
                    const RayQuery& q = rays[i];
                    RTCRayHit rh;
                    rh.ray.org_x = q.org[0], rh.ray.org_y = q.org[1], rh.ray.org_z = q.org[2];
                    rh.ray.dir_x = q.dir[0], rh.ray.dir_y = q.dir[1], rh.ray.dir_z = q.dir[2];
                    rh.ray.tnear = q.tnear, rh.ray.tfar = q.tfar;
                    rh.ray.time = 0, rh.ray.mask = 0xFFFFFFFFu, rh.ray.id = 0, rh.ray.flags = 0;
                    if (q.shadow) {
                        rtcOccluded1(accel.handle(), &ctx, &rh.ray);
                    } else {
                        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
                        rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
                        rtcIntersect1(accel.handle(), &ctx, &rh);
                    }
                }
            });
        });
        const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        rates.push_back(static_cast<double>(rays.size()) / secs);
    }
    std::sort(rates.begin(), rates.end());
    return rates[rates.size() / 2];
}

struct Options {
    int size = 256, threads = 0, split = 1, repeats = 3;
    std::string tracer = "automatic";
    std::uint32_t spp = 16;
    std::string estimator = "phong";
};

void benchScene(const std::string& spec, const Options& o) {
    const Scene scene = spec == "sphere2m" ? sphereInCornellBox() : loadScene(spec);
    Accel accel(scene);
    const auto estimator = makeEstimator(o.estimator);
    RenderSettings rs;
    rs.width = rs.height = o.size;
    rs.spp = o.spp;
    rs.trace.firstHitSplit = o.split;
    rs.trace.tracer = o.tracer == "recursive"   ? TracerChoice::Recursive
                      : o.tracer == "wavefront" ? TracerChoice::Wavefront
                                                : TracerChoice::Automatic;
    std::vector<RayQuery> rays;
    rs.threads = 1;
    accel.record(&rays);
    const RenderResult recorded = render(scene, accel, *estimator, rs);
    accel.record(nullptr);
    rs.threads = o.threads;
    std::vector<double> seconds;
    RenderResult r;
    for (int pass = 0; pass < o.repeats; ++pass) {
        r = render(scene, accel, *estimator, rs);
        seconds.push_back(r.stats.seconds);
    }
    std::sort(seconds.begin(), seconds.end());
    const double ours = static_cast<double>(r.stats.rays) / seconds[seconds.size() / 2];
    const double embree = replayRate(accel, rays, o.threads, o.repeats, false);
    const double packets = replayRate(accel, rays, o.threads, o.repeats, true);
    if (recorded.stats.rays != rays.size() || r.stats.rays != rays.size())
        fmt::print(stderr, "bench_limit: {} rays recorded, {} and {} counted\n", rays.size(), recorded.stats.rays, r.stats.rays);
    fmt::print("| {} | {} | {} | {}x{}, {} spp{} | {:.2f} s | {:.1f} M | {:.2f} | {:.2f} | {:.2f} | {:.2f} | {:.2f} |\n", scene.name,
               scene.triangles.size(), o.estimator, o.size, o.size, o.spp,
               o.split > 1                                                          ? fmt::format(", --split {}", o.split)
               : PathTracer(scene, accel, *estimator, rs.trace).tracesAsWavefront() ? ", wavefront"
                                                                                    : "",
               seconds[seconds.size() / 2], static_cast<double>(rays.size()) / 1e6, ours / 1e6, embree / 1e6, ours / embree, packets / 1e6,
               ours / packets);
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"symphong: a render's rays/s beside Embree's alone on the same rays"};
    Options o;
    o.threads = static_cast<int>(std::thread::hardware_concurrency());
    std::vector<std::string> scenes = {"cornell", "scenes/cornell-glossy-100.json", "scenes/textured.json", "sphere2m"};
    app.add_option("--scenes", scenes, "scene specs (sphere2m: the Cornell box with a 2M-triangle sphere)")
        ->delimiter(',')
        ->capture_default_str();
    app.add_option("--size", o.size, "image width and height")->capture_default_str();
    app.add_option("--spp", o.spp, "samples per pixel")->capture_default_str();
    app.add_option("--threads", o.threads, "threads of the timed render and of the replay")->capture_default_str();
    app.add_option("--estimator", o.estimator, "estimator")->capture_default_str();
    app.add_option("--split", o.split, "first-hit splitting")->capture_default_str();
    app.add_option("--repeats", o.repeats, "timed renders and replays (medians)")->capture_default_str();
    app.add_option("--tracer", o.tracer, "which tracer takes the camera samples where both can (TraceSettings::tracer)")
        ->check(CLI::IsMember({"automatic", "recursive", "wavefront"}))
        ->capture_default_str();
    CLI11_PARSE(app, argc, argv);
    fmt::print("threads: {}; medians of {} renders and {} replays\n\n", o.threads, o.repeats, o.repeats);
    fmt::print(
        "| scene | triangles | estimator | render | render time | rays | renderer Mrays/s | Embree alone Mrays/s | ratio | Embree alone, "
        "packets of 16, Mrays/s | ratio |\n");
    fmt::print("|---|---:|---|---|---:|---:|---:|---:|---:|---:|---:|\n");
    for (const std::string& s : scenes) benchScene(s, o);
    return 0;
}
