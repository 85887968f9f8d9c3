// --splitting ears rests (splitting/learning.h kRestBelowExtraPaths): after an epoch whose vertices split
// nothing, under a roulette floor, the rest of the render looks up and records no factor (one continuation a vertex, roulette by throughput).
// The decision against constructed epochs; which study scenes rest (the sun and the diffuse box, not the
// smooth sky); a resting render traces its later epochs as factors that split nothing would,
// records and learns nothing more, stays unbiased, the same at any thread count, and resumes from a
// checkpoint bit for bit; the independent sampler never rests.
#include "ears_settings.h"
#include "estimators/registry.h"
#include "render/checkpoint.h"
#include "render/renderer.h"
#include "scene/scene.h"
#include "splitting/learning.h"
#include "test_util.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

using namespace symphong;
using symphong::test::earsSettings;

namespace {

std::string scenePath(const std::string& name) { return std::string(SYMPHONG_SOURCE_DIR) + "/scenes/" + name; }

bool sameBits(const Image& a, const Image& b) { return a.pixels == b.pixels; }

}  // namespace

// The rule on its own: an epoch from kRestFromEpoch on whose paths exceed its camera samples by less than
// kRestBelowExtraPaths of them rests, when the render may rest; one more extra path, an earlier epoch, a
// render that may not, or an epoch whose paths at its start are unknown (an older checkpoint's) does not.
TEST(EarsRest, AnEpochThatSplitNothingRests) {
    const auto epochEnd = [](int epoch, std::uint64_t extra, bool mayRest, std::uint64_t pathsAtStart = 500) {
        ears::Learning l(ears::Grid(Vec3(0.0), Vec3(1.0)));
        l.epoch = epoch, l.samplesAtStart = 400, l.pathsAtStart = pathsAtStart, l.raysAtStart = 1000;
        // 10,000 camera samples in the epoch: kRestBelowExtraPaths allows fewer than 100 extra paths.
        l.advance(0.5, 50000, 10400, (pathsAtStart == ears::kUnknownPaths ? 500 : pathsAtStart) + 10000 + extra, mayRest);
        return l.resting;
    };
    EXPECT_TRUE(epochEnd(1, 0, true));
    EXPECT_TRUE(epochEnd(1, 99, true));
    EXPECT_FALSE(epochEnd(1, 100, true));
    EXPECT_TRUE(epochEnd(2, 99, true));
    EXPECT_TRUE(epochEnd(5, 40, true));
    EXPECT_FALSE(epochEnd(0, 0, true)) << "epoch 0's deeper vertices are unlearned";
    EXPECT_FALSE(epochEnd(1, 0, false)) << "no roulette floor: no rest";
    EXPECT_FALSE(epochEnd(1, 0, true, ears::kUnknownPaths));
}

// The epoch that decides to rest learns nothing: its factors stay the ones it rendered with (an epoch that
// does not rest replaces them by what its records say), its sums are emptied, and the next epoch begins.
TEST(EarsRest, TheEpochThatRestsLearnsNothing) {
    const auto epochEnd = [](bool rests) {
        ears::Learning l(ears::Grid(Vec3(0.0), Vec3(1.0)));
        l.epoch = 1, l.samplesAtStart = 400, l.pathsAtStart = 500, l.raysAtStart = 1000;
        l.factors.reset(ears::Grid::cellCount());
        std::fill(l.factors.firstHit.begin(), l.factors.firstHit.end(), 4.0f);
        l.add(ears::Record(static_cast<std::uint32_t>(l.grid.cell(Vec3(0.5), ears::Grid::kLevels - 1)), 2.0, 3, ears::Section::Deeper));
        l.advance(0.5, 50000, 10400, 500 + 10000 + (rests ? 0 : 5000), true);
        EXPECT_EQ(l.resting, rests);
        EXPECT_EQ(l.epoch, 2);
        EXPECT_EQ(l.pathsAtStart, rests ? 10500u : 15500u);
        EXPECT_EQ(l.samplesAtStart, 10400u);
        std::size_t occupied = 0;
        l.occupied().forEach(0, l.occupied().capacity(), [&](std::size_t) { ++occupied; });
        EXPECT_EQ(occupied, 0u);
        return l.factors;
    };
    const ears::Factors kept = epochEnd(true);
    ASSERT_EQ(kept.firstHit.size(), ears::Grid::cellCount());
    EXPECT_TRUE(std::all_of(kept.firstHit.begin(), kept.firstHit.end(), [](float f) { return f == 4.0f; }));
    const ears::Factors learned = epochEnd(false);
    EXPECT_FALSE(!learned.firstHit.empty() &&
                 std::all_of(learned.firstHit.begin(), learned.firstHit.end(), [](float f) { return f == 4.0f; }));
}

// Which scenes rest, at the study's size and spp under sobol: the sun (whose first hits and deeper vertices
// EARS splits nowhere) and the diffuse box rest, by the end of epoch 1; the smooth sky, whose first hits it
// splits everywhere, does not. Resting, the render records nothing more and its epoch stops.
TEST(EarsRest, TheSunRestsAndTheSmoothSkyDoesNot) {
    const auto est = makeEstimator("phong");
    for (const auto& [name, rests] :
         {std::pair<std::string, bool>{"regime/sun-n10.json", true}, {"cornell-diffuse.json", true}, {"regime/sky-n10.json", false}}) {
        const Scene scene = loadScene(scenePath(name));
        const Accel accel(scene);
        const RenderSettings rs = earsSettings(128, 96, 16, 1);
        RenderState state(128, 96, 16);
        renderSamples(scene, accel, *est, rs, state, 16);
        ASSERT_TRUE(state.ears) << name;
        EXPECT_EQ(state.ears->resting, rests) << name;
        if (rests) {
            EXPECT_EQ(state.ears->epoch, ears::kRestFromEpoch + 1) << name << ": no epoch ended after the rest began";
            std::uint64_t recorded = 0;
            for (const ears::CellSums& c : state.ears->sums()) recorded += c.count;
            EXPECT_EQ(recorded, 0u) << name;
        }
    }
}

// A resting render traces its later samples as learned factors that split nothing would: one continuation
// at every first hit and plain roulette by throughput deeper, as a cell without estimates gets. The second
// method: the same state with the rest undone and its factors replaced by exactly that (every first hit's
// factor 1, no deeper estimate, no MIS share), rendered on with lookups and records, gives
// the same image and rays bit for bit. Plain phong (--splitting none) traces fewer rays: its roulette
// takes the throughput after the direction's weight.
TEST(EarsRest, RestingTracesWhatFactorsThatSplitNothingTrace) {
    const Scene scene = loadScene(scenePath("regime/sun-n10.json"));
    const Accel accel(scene);
    const auto est = makeEstimator("phong");
    const RenderSettings rs = earsSettings(64, 48, 16, 5);
    RenderState resting(64, 48, 16);
    renderSamples(scene, accel, *est, rs, resting, 8);
    ASSERT_TRUE(resting.ears && resting.ears->resting);
    RenderState learned = resting;
    learned.ears->resting = false;
    learned.ears->factors.reset(ears::Grid::cellCount());
    std::fill(learned.ears->factors.firstHit.begin(), learned.ears->factors.firstHit.end(), 1.0f);
    const std::uint64_t before = resting.rays;
    renderSamples(scene, accel, *est, rs, resting, 16);
    renderSamples(scene, accel, *est, rs, learned, 16);
    EXPECT_TRUE(sameBits(resting.image(), learned.image()));
    EXPECT_EQ(resting.rays, learned.rays);
    EXPECT_GT(resting.rays - before, 64u * 48u * 8u);
}

// Unbiased when it rests: the mean image of a resting render of the sun scene (sobol, 64 spp) against plain
// phong's under the independent sampler (independent seeds; each its own standard error, which under sobol
// overstates the error: a conservative z), |z| < 4.
TEST(EarsRest, RestingRendersAgreeWithPhong) {
    const Scene scene = loadScene(scenePath("regime/sun-n10.json"));
    const Accel accel(scene);
    const auto est = makeEstimator("phong");
    RenderSettings rs = earsSettings(40, 30, 64, 2031);
    RenderState state(40, 30, 64);
    renderSamples(scene, accel, *est, rs, state, 64);
    ASSERT_TRUE(state.ears->resting);
    const auto [me, se] = test::imageMeanAndError(resultOf(state, "sobol"));
    rs = earsSettings(40, 30, 256, 2032, "independent");
    rs.trace.splitting = SplittingMode::None;
    const auto [mp, sp] = test::imageMeanAndError(render(scene, accel, *est, rs));
    const double z = (me - mp) / std::sqrt(se * se + sp * sp);
    std::printf("resting ears %.5f +- %.5f, phong %.5f +- %.5f, z %+.2f\n", me, se, mp, sp, z);
    EXPECT_LT(std::abs(z), 4.0);
}

// The same image at any thread count, and resumed from a checkpoint taken after the rest began (12 of 32
// samples) bit for bit; the checkpoint carries the rest.
TEST(EarsRest, SameImageAtAnyThreadCountAndResumedBitForBit) {
    const Scene scene = loadScene(scenePath("regime/sun-n10.json"));
    const Accel accel(scene);
    const auto est = makeEstimator("phong");
    RenderSettings rs = earsSettings(64, 48, 32, 9);
    rs.threads = 1;
    RenderState one(64, 48, 32);
    renderSamples(scene, accel, *est, rs, one, 32);
    ASSERT_TRUE(one.ears->resting);
    rs.threads = 2;
    RenderState two(64, 48, 32);
    renderSamples(scene, accel, *est, rs, two, 32);
    EXPECT_TRUE(sameBits(one.image(), two.image()));
    RenderState part(64, 48, 32);
    renderSamples(scene, accel, *est, rs, part, 12);
    ASSERT_TRUE(part.ears->resting);
    const test::TempDir tmp;
    const std::string path = tmp.file("rest.ckpt");
    writeCheckpoint(path, RenderIdentity{"sun-n10", "0", nlohmann::json::object()}, part);
    RenderIdentity id;
    RenderState resumed;
    readCheckpoint(path, id, resumed);
    ASSERT_TRUE(resumed.ears);
    EXPECT_TRUE(resumed.ears->resting);
    EXPECT_EQ(resumed.ears->pathsAtStart, part.ears->pathsAtStart);
    renderSamples(scene, accel, *est, rs, resumed, 32);
    EXPECT_TRUE(sameBits(one.image(), resumed.image()));
    EXPECT_TRUE(sameBits(one.variance(), resumed.variance()));
}

// Under the independent sampler EARS's roulette may be harder than plain roulette's: it never rests there.
TEST(EarsRest, TheIndependentSamplerNeverRests) {
    const Scene scene = loadScene(scenePath("regime/sun-n10.json"));
    const Accel accel(scene);
    const auto est = makeEstimator("phong");
    const RenderSettings rs = earsSettings(64, 48, 32, 3, "independent");
    RenderState state(64, 48, 32);
    renderSamples(scene, accel, *est, rs, state, 32);
    EXPECT_FALSE(state.ears->resting);
}
