// render/wavefront.cpp: a batch of camera samples' paths depth by depth (TraceSettings::tracer) against the
// recursive tracer (shade() calling itself), the second method: the same decisions at the same sample
// dimensions, so the same paths and rays, and each path's terms summed back from its last vertex in shade()'s
// order, so each pixel the same value bit for bit. A path that drew from another dimension (or took a value the
// sampler's lanes computed wrong), kept a vertex's term at the wrong weight, lost a path or ended one early
// differs. Compared on an Accel that traces each ray alone, as the recursive tracer does; with the renderer's packets
// (a depth's bounce and shadow rays 16 at a time), the same but for the few rays whose answer a packet rounds
// otherwise.
#include "estimators/estimator.h"
#include "render/path_tracer.h"
#include "render/renderer.h"
#include "sampling/sobol_lanes.h"
#include "scene/scene.h"
#include "test_util.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <string>

using namespace symphong;

namespace {

struct Case {
    std::string scene, estimator;
    std::function<void(RenderSettings&)> tweak = [](RenderSettings&) {};
    EstimatorOptions options = {};
};

RenderSettings settingsOf(const Case& c, bool wavefront) {
    RenderSettings rs;
    rs.width = 24;
    rs.height = 18;
    rs.spp = 21;  // a packet of 16 spans pixels; the last of a pixel's samples go with the next pixel's
    rs.seed = 5;
    rs.threads = 2;
    c.tweak(rs);
    rs.trace.tracer = wavefront ? TracerChoice::Wavefront : TracerChoice::Recursive;
    return rs;
}

std::vector<Case> cases() {
    const std::string dir = std::string(SYMPHONG_SOURCE_DIR) + "/scenes/";
    EstimatorOptions spread;
    spread.symmetricMode = SymmetricMode::Spread;
    std::vector<Case> list = {
        {"cornell", "phong"},
        {dir + "cornell-glossy-100.json", "phong"},
        {dir + "textured.json", "phong"},  // textures, a normal map, an HDR sky sampled by MIS
        {dir + "regime/sky-n10.json", "phong"},
        // Delta lights (point, spot, directional) beside an area light: light samples of both kinds at one depth.
        {std::string(SYMPHONG_SOURCE_DIR) + "/tests/golden/lights.json", "phong"},
        {"cornell", "cosine", [](RenderSettings& rs) { rs.trace.nextEvent = false; }},
        {"cornell", "phong", [](RenderSettings& rs) { rs.trace.maxDepth = 2, rs.trace.rrDepth = 1; }},
        {"cornell", "phong", [](RenderSettings& rs) { rs.trace.firstBounceStream = 3; }},
        {"cornell", "phong", [](RenderSettings& rs) { rs.sampler = "independent"; }},
        {"cornell", "symmetric-mix", [](RenderSettings&) {}, spread},  // one direction a call
        // A power-of-two spp: the sampler's values computed ahead in vector lanes where the processor has them
        // (sobol_lanes.h; 21 spp above takes the scalar form), the batch spanning many pixels.
        {"cornell", "phong", [](RenderSettings& rs) { rs.spp = 32; }},
        {dir + "textured.json", "phong", [](RenderSettings& rs) { rs.spp = 16; }},
        {"cornell", "phong", [](RenderSettings& rs) { rs.spp = 1; }},
        // A branching first hit: --split k (k calls on sub-samples), and sets (continuations 1..P of their own),
        // with and without their values computed ahead; roulette from the first continuation on.
        {"cornell", "phong", [](RenderSettings& rs) { rs.trace.firstHitSplit = 2; }},
        {"cornell", "phong", [](RenderSettings& rs) { rs.trace.firstHitSplit = 3, rs.spp = 16; }},
        {"cornell", "phong", [](RenderSettings& rs) { rs.trace.firstHitSplit = 2, rs.spp = 32; }},  // k x spp in the lanes
        {"cornell", "phong", [](RenderSettings& rs) { rs.trace.firstHitSplit = 0, rs.spp = 32; }},  // the library's k below 1: k = 1
        {dir + "cornell-glossy-100.json", "phong", [](RenderSettings& rs) { rs.trace.firstHitSplit = 2, rs.trace.rrDepth = 1; }},
        {dir + "textured.json", "phong", [](RenderSettings& rs) { rs.trace.firstHitSplit = 4, rs.spp = 8; }},
        {"cornell", "symmetric", [](RenderSettings& rs) { rs.spp = 4; }},
        {"cornell", "symmetric-mix", [](RenderSettings& rs) { rs.spp = 16, rs.trace.firstHitSplit = 2; }},
        {"cornell", "paper", [](RenderSettings& rs) { rs.spp = 4, rs.trace.nextEvent = false; }},
    };
    if (!test::scenesDir().empty()) list.push_back({test::scenesDir() + "/bunny/stanford-bunny.obj", "phong"});
    return list;
}

}  // namespace

TEST(Wavefront, TracesThePathsTheRecursiveTracerTraces) {
    for (const Case& c : cases()) {
        const Scene scene = loadScene(c.scene);
        const Accel accel(scene, false);  // a depth's rays one by one, as the recursive tracer asks them
        const auto estimator = makeEstimator(c.estimator, c.options);
        const RenderSettings waveSettings = settingsOf(c, true);
        ASSERT_TRUE(PathTracer(scene, accel, *estimator, waveSettings.trace).tracesAsWavefront()) << c.scene << " " << c.estimator;
        const RenderResult recursive = render(scene, accel, *estimator, settingsOf(c, false));
        const RenderResult wave = render(scene, accel, *estimator, waveSettings);
        EXPECT_EQ(wave.stats.rays, recursive.stats.rays) << c.scene << " " << c.estimator << ": the same paths trace the same rays";
        std::size_t lit = 0, differing = 0;
        double worst = 0;
        for (std::size_t i = 0; i < recursive.image.pixels.size(); ++i) {
            const Color a = recursive.image.pixels[i], b = wave.image.pixels[i];
            lit += maxComponent(a) > 0;
            worst = std::max(worst, maxComponent(vmax(a - b, b - a)) / std::max(1e-300, maxComponent(a)));
            differing += !(a.x == b.x && a.y == b.y && a.z == b.z);
        }
        // The comparison saw light (without light sampling, 21 samples find the box's small light in a sixth of the pixels).
        EXPECT_GT(lit, recursive.image.pixels.size() / 8) << c.scene << " " << c.estimator;
        EXPECT_EQ(differing, 0u) << c.scene << " " << c.estimator << " spp " << waveSettings.spp << ": worst relative difference " << worst;
    }
}

// With a depth's rays in 16-wide packets (the renderer's Accel), only the answers of rays that a packet's kernels
// decide otherwise than the single-ray ones differ: a grazing ray at an edge, in float round-off. The same
// images but for a few pixels, the same rays but for a few. Where the device has no packets, the exact test above.
TEST(Wavefront, WithPacketsTheSameImageButWhereAPacketRoundsOtherwise) {
    std::size_t allDiffering = 0, allPixels = 0;
    for (const Case& c : cases()) {
        const Scene scene = loadScene(c.scene);
        const Accel single(scene, false), packets(scene);
        const auto estimator = makeEstimator(c.estimator, c.options);
        const RenderResult recursive = render(scene, single, *estimator, settingsOf(c, false));
        const RenderResult wave = render(scene, packets, *estimator, settingsOf(c, true));
        EXPECT_NEAR(static_cast<double>(wave.stats.rays), static_cast<double>(recursive.stats.rays),
                    1e-3 * static_cast<double>(recursive.stats.rays))
            << c.scene << " " << c.estimator;
        std::size_t differing = 0;
        for (std::size_t i = 0; i < recursive.image.pixels.size(); ++i) {
            const Color a = recursive.image.pixels[i], b = wave.image.pixels[i];
            differing += !(a.x == b.x && a.y == b.y && a.z == b.z);
        }
        EXPECT_LE(differing, recursive.image.pixels.size() / 50) << c.scene << " " << c.estimator << ": pixels that differ";
        allDiffering += differing;
        allPixels += recursive.image.pixels.size();
    }
    EXPECT_LE(allDiffering, allPixels / 200) << "over all cases";
}

TEST(Wavefront, OnlyWhereABatchHoldsAFirstHitsContinuations) {
    const Scene scene = loadScene("cornell");
    const Accel accel(scene);
    const auto phong = makeEstimator("phong");
    TraceSettings on;
    on.tracer = TracerChoice::Wavefront;
    EXPECT_TRUE(PathTracer(scene, accel, *phong, on).tracesAsWavefront());
    TraceSettings off;
    off.tracer = TracerChoice::Recursive;
    EXPECT_FALSE(PathTracer(scene, accel, *phong, off).tracesAsWavefront());
    EXPECT_EQ(PathTracer(scene, accel, *phong, TraceSettings{}).tracesAsWavefront(), sobolLanesAvailable())
        << "automatic: the wavefront where the sampler's lanes run";
    TraceSettings split = on;
    split.firstHitSplit = 2;
    EXPECT_TRUE(PathTracer(scene, accel, *phong, split).tracesAsWavefront()) << "a first hit's branches in slots of their own";
    EXPECT_EQ(PathTracer(scene, accel, *phong, split).cameraBatch(), WavefrontBatch::kSize / 2);
    TraceSettings joint = on;
    joint.jointFirstBounce = true;
    EXPECT_FALSE(PathTracer(scene, accel, *phong, joint).tracesAsWavefront());
    EstimatorOptions branch;
    branch.symmetricMode = SymmetricMode::Branch;
    const auto sets = makeEstimator("symmetric", branch);
    EXPECT_TRUE(PathTracer(scene, accel, *sets, on).tracesAsWavefront()) << "a set of 24 directions";
    EXPECT_EQ(PathTracer(scene, accel, *sets, on).cameraBatch(), WavefrontBatch::kSize / 24);
    EXPECT_FALSE(PathTracer(scene, accel, *sets, TraceSettings{}).tracesAsWavefront()) << "automatic: no faster for sets of 24";
    TraceSettings split16;
    split16.firstHitSplit = 16;
    EXPECT_EQ(PathTracer(scene, accel, *phong, split16).tracesAsWavefront(), sobolLanesAvailable()) << "automatic: --split 16";
    branch.symmetricN = 11;  // 264 directions a set: more than a batch holds
    EXPECT_FALSE(PathTracer(scene, accel, *makeEstimator("symmetric", branch), on).tracesAsWavefront());
    TraceSettings wide = on;
    wide.firstHitSplit = 257;
    EXPECT_FALSE(PathTracer(scene, accel, *phong, wide).tracesAsWavefront());
}
