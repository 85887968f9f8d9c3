// Renders in passes (render/progressive.h, render/render_state.h) and their checkpoints
// (render/checkpoint.h): passes in any order, tile by tile, give the one-pass image and variance bit for
// bit with every sampler; the error estimate of the image mean agrees with the spread of the mean over
// seeds (a second method); --target-error stops within the stated error of a high-spp reference over
// repeats; --time stops after the first pass that reaches the limit; a checkpoint reads back exactly and
// a damaged one is refused. The command line's kill -9, signals and refusals are in
// tests/render/checkpoint_checks.sh.
#include "test_util.h"

#include "io/input_error.h"
#include "render/checkpoint.h"
#include "render/progressive.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <mutex>

using namespace symphong;

namespace {

RenderSettings tinySettings(int w, int h, std::uint32_t spp, const std::string& sampler, std::uint64_t seed = 7) {
    RenderSettings s;
    s.width = w, s.height = h, s.spp = spp, s.seed = seed, s.sampler = sampler, s.threads = 2;
    return s;
}

/// Hands out the tiles of a list, once each.
class ListSource : public TileSource {
public:
    explicit ListSource(std::vector<int> tiles) : tiles_(std::move(tiles)) {}
    bool next(int& tile) override {
        std::lock_guard lock(mutex_);
        if (next_ == tiles_.size()) return false;
        tile = tiles_[next_++];
        return true;
    }

private:
    std::vector<int> tiles_;
    std::size_t next_ = 0;
    std::mutex mutex_;
};

void expectSameBits(const Image& a, const Image& b, const std::string& what) {
    ASSERT_EQ(a.pixels.size(), b.pixels.size());
    EXPECT_EQ(std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(Color)), 0) << what;
}

}  // namespace

TEST(Progressive, PassesInAnyOrderGiveTheOnePassImageBitForBit) {
    const Scene scene = makeCornellBox();
    const Accel accel(scene);
    for (const std::string sampler : {"independent", "stratified", "sobol"})
        for (const std::string name : {"phong", "symmetric-mix"}) {
            const auto est = makeEstimator(name);
            const RenderSettings s = tinySettings(40, 36, 13, sampler);
            const RenderResult once = render(scene, accel, *est, s);
            // The even tiles first, all the way; then every tile to 5 samples (the even ones have them);
            // then every tile in passes of 3 to the end.
            RenderState state(s.width, s.height, s.spp);
            std::vector<int> even;
            for (int t = 0; t < tileCount(s.width, s.height); t += 2) even.push_back(t);
            ListSource evenTiles(even);
            RenderSettings some = s;
            some.tiles = &evenTiles;
            renderSamples(scene, accel, *est, some, state, 13);
            renderSamples(scene, accel, *est, s, state, 5);
            EXPECT_EQ(state.samplesReached(), 5u);
            for (std::uint32_t upTo = 8; upTo <= 14; upTo += 3) renderSamples(scene, accel, *est, s, state, upTo);
            EXPECT_TRUE(state.finished());
            const std::string what = sampler + ", " + name;
            expectSameBits(once.image, state.image(), what + ": image");
            expectSameBits(once.variance, state.variance(), what + ": variance");
            EXPECT_EQ(state.samples, static_cast<std::uint64_t>(s.width) * s.height * s.spp) << what;
        }
}

// The standard error the state reports for the image mean against the spread of that mean over 100
// seeds: the two estimate the same standard deviation (the second with a relative standard error of
// 1/sqrt(2 x 99) = 7%).
TEST(Progressive, ErrorEstimateOfTheMeanMatchesItsSpreadOverSeeds) {
    const Scene scene = makeCornellBox();
    const Accel accel(scene);
    const auto est = makeEstimator("phong");
    std::vector<double> means;
    double reported = 0;
    const int seeds = 100;
    for (int seed = 1; seed <= seeds; ++seed) {
        const RenderSettings s = tinySettings(16, 16, 8, "independent", static_cast<std::uint64_t>(seed));
        RenderState state(s.width, s.height, s.spp);
        renderSamples(scene, accel, *est, s, state, s.spp);
        const MeanError e = state.regionError({0, 0, 16, 16});
        means.push_back(e.mean);
        reported += e.stdError * e.stdError / seeds;
    }
    double m = 0, v = 0;
    for (double x : means) m += x / seeds;
    for (double x : means) v += (x - m) * (x - m) / (seeds - 1);
    const double spread = std::sqrt(v), estimate = std::sqrt(reported);
    EXPECT_NEAR(estimate / spread, 1.0, 4 / std::sqrt(2.0 * (seeds - 1))) << "reported " << estimate << ", spread " << spread;
}

// Thirty renders stopped by --target-error E = 8% (independent seeds): each stops with its own estimate
// at most E, before the spp bound; the root mean square of their true relative errors (against a 4096 spp
// reference) is E within 4 standard errors of an RMS of 30 (relative 1/sqrt(60)), not far below it (a
// render that ignored the target would run to the bound: an error 8x smaller).
TEST(Progressive, TargetErrorStopsWithinTheStatedError) {
    const Scene scene = makeCornellBox();
    const Accel accel(scene);
    const auto est = makeEstimator("phong");
    RenderState reference(16, 16, 4096);
    renderSamples(scene, accel, *est, tinySettings(16, 16, 4096, "independent", 999), reference, 4096);
    const MeanError ref = reference.regionError({0, 0, 16, 16});
    const double target = 0.08;
    ASSERT_LT(ref.relative(), target / 10);
    StopRules rules;
    rules.targetError = target;
    double sumSq = 0;
    const int repeats = 30;
    for (int r = 0; r < repeats; ++r) {
        const RenderSettings s = tinySettings(16, 16, 1024, "independent", 100 + static_cast<std::uint64_t>(r));
        RenderState state(16, 16, 1024);
        const StopReason why = renderProgressive(scene, accel, *est, s, rules, state, nullptr);
        ASSERT_EQ(why, StopReason::TargetError) << "repeat " << r;
        EXPECT_LE(worstRelativeError(state, {}), target);
        EXPECT_LT(state.samplesReached(), 1024u);
        const double d = (state.regionError({0, 0, 16, 16}).mean - ref.mean) / ref.mean;
        sumSq += d * d;
    }
    const double rms = std::sqrt(sumSq / repeats), slack = 4 / std::sqrt(2.0 * repeats);
    EXPECT_LE(rms, target * (1 + slack) + 3 * ref.relative()) << "RMS relative error " << rms;
    EXPECT_GE(rms, target * (1 - slack) * 0.6) << "RMS relative error " << rms << ": stopped much later than needed";
}

// The time limit is checked after each pass: the render stops after the first pass that ends at or
// beyond it, so every earlier pass ended before it.
TEST(Progressive, TimeLimitStopsAfterThePassThatReachesIt) {
    const Scene scene = makeCornellBox();
    const Accel accel(scene);
    const auto est = makeEstimator("phong");
    StopRules rules;
    rules.timeLimit = 0.3;
    rules.passSpp = 1;
    const RenderSettings s = tinySettings(64, 64, 100000, "sobol");
    RenderState state(s.width, s.height, s.spp);
    std::vector<PassReport> reports;
    const StopReason why = renderProgressive(scene, accel, *est, s, rules, state, [&](const PassReport& r) { reports.push_back(r); });
    ASSERT_EQ(why, StopReason::Time);
    ASSERT_FALSE(reports.empty());
    EXPECT_TRUE(reports.back().last);
    EXPECT_GE(reports.back().seconds, rules.timeLimit);
    for (std::size_t i = 0; i + 1 < reports.size(); ++i) {
        EXPECT_LT(reports[i].seconds, rules.timeLimit) << "pass " << i;
        EXPECT_FALSE(reports[i].last);
        EXPECT_EQ(reports[i].samplesReached, i + 1) << "passes of one sample";
    }
    EXPECT_EQ(state.samplesReached(), reports.size());
}

// --target-error with regions: the render stops only when every region's mean is within the target. A
// 3 x 3 corner of the box needs many more samples than the whole image (at the 4 samples from which the error
// is trusted its relative error is several times 5%); each region's relative error is computed here from the
// state's sums (one tile: every pixel has the same n), not by regionError.
TEST(Progressive, TargetErrorWaitsForItsWorstRegion) {
    const Scene scene = makeCornellBox();
    const Accel accel(scene);
    const auto est = makeEstimator("phong");
    StopRules rules;
    rules.targetError = 0.05;
    rules.regions = {{0, 0, 16, 16}, {0, 0, 3, 3}};
    const RenderSettings s = tinySettings(16, 16, 4096, "independent", 3);
    RenderState state(16, 16, 4096);
    ASSERT_EQ(state.tileSamples.size(), 1u);
    const auto relativeError = [&](const PixelRect& r) {
        const double n = state.tileSamples[0];
        double mean = 0, variance = 0;
        for (int y = r.y; y < r.y + r.height; ++y)
            for (int x = r.x; x < r.x + r.width; ++x) {
                const std::size_t p = static_cast<std::size_t>(y * 16 + x);
                const double sy = luminance(state.sum[p]);
                mean += sy / n;
                variance += (state.sumLuminanceSq[p] - sy * sy / n) / (n - 1) / n;  // of the pixel's mean
            }
        return std::sqrt(variance) / mean;  // the region's mean is the sum over count: count cancels
    };
    ASSERT_EQ(renderProgressive(scene, accel, *est, s, rules, state, nullptr), StopReason::TargetError);
    EXPECT_LE(relativeError(rules.regions[0]), rules.targetError);
    EXPECT_LE(relativeError(rules.regions[1]), rules.targetError) << state.samplesReached() << " spp";
    EXPECT_LT(state.samplesReached(), 4096u);
    // Power: the whole image alone is within the target far sooner than the corner.
    RenderState whole(16, 16, 4096);
    StopRules image = rules;
    image.regions = {rules.regions[0]};
    ASSERT_EQ(renderProgressive(scene, accel, *est, s, image, whole, nullptr), StopReason::TargetError);
    EXPECT_LT(4 * whole.samplesReached(), state.samplesReached());
}

// Automatic passes under --time: each is sized to the time left at the speed measured so far, so the render
// ends near the limit, not after a whole pass of rules.passSeconds (4 s here, ten times the limit).
TEST(Progressive, TimeLimitSizesThePassesToTheTimeLeft) {
    const Scene scene = makeCornellBox();
    const Accel accel(scene);
    const auto est = makeEstimator("phong");
    StopRules rules;
    rules.timeLimit = 0.4;
    rules.passSeconds = 4;
    const RenderSettings s = tinySettings(64, 64, 1000000, "sobol");
    {  // A real render: it stops on time, within a generous bound (wall time on a busy machine).
        RenderState state(s.width, s.height, s.spp);
        ASSERT_EQ(renderProgressive(scene, accel, *est, s, rules, state, nullptr), StopReason::Time);
        EXPECT_GE(state.seconds, rules.timeLimit);
        EXPECT_LT(state.seconds, 10 * rules.timeLimit) << state.samplesReached() << " spp";
    }
    // The sizing itself, on a clock of its own (each sample per pixel takes exactly 1 ms, whatever the
    // machine's load): the first pass is 1 spp, the second fills the time left, 399 spp, and the render
    // stops at exactly 0.4 s. Sized by passSeconds alone, the second pass would be 3999 spp (4 s).
    RenderState state(s.width, s.height, s.spp);
    std::vector<std::uint32_t> passes;
    const PassRunner clock = [&](RenderState& st, std::uint32_t upTo) {
        passes.push_back(upTo - st.samplesReached());
        st.seconds += 0.001 * (upTo - st.samplesReached());
        std::fill(st.tileSamples.begin(), st.tileSamples.end(), upTo);
    };
    ASSERT_EQ(renderProgressive(scene, accel, *est, s, rules, state, nullptr, nullptr, clock), StopReason::Time);
    EXPECT_EQ(passes, (std::vector<std::uint32_t>{1, 399}));
    EXPECT_NEAR(state.seconds, rules.timeLimit, 1e-9);
}

TEST(Checkpoint, ReadsBackExactlyAndResumesToTheOnePassImage) {
    const Scene scene = makeCornellBox();
    const Accel accel(scene);
    const auto est = makeEstimator("phong");
    const RenderSettings s = tinySettings(33, 20, 10, "sobol");
    RenderState state(s.width, s.height, s.spp);
    renderSamples(scene, accel, *est, s, state, 4);
    test::TempDir dir;
    const RenderIdentity id{"cornell", sceneFingerprint(scene, "cornell"), {{"spp", 10}, {"seed", 7}}};
    writeCheckpoint(dir.file("a.ckpt"), id, state);
    RenderIdentity back;
    RenderState read;
    readCheckpoint(dir.file("a.ckpt"), back, read);
    EXPECT_EQ(back.scene, id.scene);
    EXPECT_EQ(back.sceneHash, id.sceneHash);
    EXPECT_EQ(back.settings, id.settings);
    EXPECT_NO_THROW(requireSameRender("a.ckpt", back, id));
    EXPECT_EQ(read.tileSamples, state.tileSamples);
    EXPECT_EQ(std::memcmp(read.sum.data(), state.sum.data(), state.sum.size() * sizeof(Color)), 0);
    EXPECT_EQ(std::memcmp(read.sumSq.data(), state.sumSq.data(), state.sumSq.size() * sizeof(Color)), 0);
    EXPECT_EQ(read.sumLuminanceSq, state.sumLuminanceSq);
    EXPECT_EQ(read.rays, state.rays);
    EXPECT_EQ(read.seconds, state.seconds);
    renderSamples(scene, accel, *est, s, read, 10);
    expectSameBits(render(scene, accel, *est, s).image, read.image(), "resumed");
}

// A rank of a killed MPI job lives on for up to a second and may rename its checkpoint over the one that
// the next job is reading (CI's mpi.resume-kill read one file's header against the other's size: "1153416
// bytes where its header needs 1153364"). A reader holds the file it opened: its bytes and its size.
TEST(Checkpoint, ReadsTheFileItOpenedWhenAnotherIsRenamedOverIt) {
    const Scene scene = makeCornellBox();
    const Accel accel(scene);
    const auto est = makeEstimator("phong");
    const RenderSettings s = tinySettings(24, 16, 6, "sobol");
    RenderState opened(s.width, s.height, s.spp);
    renderSamples(scene, accel, *est, s, opened, 2);
    test::TempDir dir;
    const RenderIdentity id{"cornell", sceneFingerprint(scene, "cornell"), {{"spp", 6}, {"seed", 7}}};
    writeCheckpoint(dir.file("a.ckpt"), id, opened);
    std::ifstream in(dir.file("a.ckpt"), std::ios::binary);
    RenderState later(40, 30, 6);  // another size: another file size
    writeCheckpoint(dir.file("a.ckpt"), id, later);
    RenderIdentity back;
    RenderState read;
    ASSERT_NO_THROW(readCheckpoint(in, dir.file("a.ckpt"), back, read));
    EXPECT_EQ(read.width, s.width);
    EXPECT_EQ(read.tileSamples, opened.tileSamples);
    EXPECT_EQ(std::memcmp(read.sum.data(), opened.sum.data(), opened.sum.size() * sizeof(Color)), 0);
    RenderState now;
    readCheckpoint(dir.file("a.ckpt"), back, now);  // and the path names the new one
    EXPECT_EQ(now.width, 40);
}

TEST(Checkpoint, DamagedOrForeignCheckpointsAreRefusedNamingTheFile) {
    const Scene scene = makeCornellBox();
    RenderState state(20, 20, 4);
    test::TempDir dir;
    const RenderIdentity id{"cornell", sceneFingerprint(scene, "cornell"), {{"spp", 4}, {"seed", 1}}};
    writeCheckpoint(dir.file("a.ckpt"), id, state);
    std::string bytes;
    {
        std::ifstream in(dir.file("a.ckpt"), std::ios::binary);
        bytes.assign(std::istreambuf_iterator<char>(in), {});
    }
    const auto refused = [&](const std::string& content, const std::string& expected) {
        dir.write("b.ckpt", content);
        RenderIdentity back;
        RenderState read;
        try {
            readCheckpoint(dir.file("b.ckpt"), back, read);
            ADD_FAILURE() << "accepted; expected: " << expected;
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find("b.ckpt: not a usable checkpoint (" + expected), std::string::npos) << e.what();
        }
    };
    std::string flipped = bytes;
    flipped[flipped.size() - 20] ^= 0x10;
    refused(flipped, "its checksum does not match");
    refused(bytes.substr(0, bytes.size() - 1), "");
    refused(bytes + "x", "");
    refused("symphong checkpoint 2\n" + bytes.substr(22), "it does not start with");
    const RenderIdentity other{"box.obj", "0123456789abcdef", id.settings};
    EXPECT_THROW(requireSameRender("a.ckpt", id, other), InputError);
    RenderIdentity seed2 = id;
    seed2.settings["seed"] = 2;
    try {
        requireSameRender("a.ckpt", id, seed2);
        ADD_FAILURE() << "another seed accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("a.ckpt: the checkpoint was made with seed 1, not 2"), std::string::npos) << e.what();
    }
}

TEST(Checkpoint, ScheduleWritesBeforeTheNextPassWouldCarryWorkPastTheInterval) {
    CheckpointSchedule s(10.0, 0.0);
    EXPECT_FALSE(s.due(4.0, 5.0, false));  // the next pass ends at 9: still within the interval
    EXPECT_TRUE(s.due(6.0, 5.0, false));   // it would end at 11: write now
    EXPECT_TRUE(s.due(1.0, 0.0, true));    // the last pass: always
    s.written(6.0);
    EXPECT_FALSE(s.due(12.0, 3.0, false));
    EXPECT_TRUE(s.due(14.0, 3.0, false));
}
