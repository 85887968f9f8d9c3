// Image-level tests on tiny renders: the closed furnace (radiance Le/(1-a) everywhere), agreement of
// all estimators on a 32x32 Cornell box within statistics, light sampling vs none (MIS is unbiased),
// and bit-for-bit determinism across thread counts.
#include "scene/scene.h"
#include "stats.h"
#include "compare/metrics.h"
#include "test_util.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>

using namespace symphong;

namespace {

/// Mean luminance over a block of pixels and its standard error (pixels are independent: one PCG
/// stream each, so the variances of their means add).
test::MeanStd blockMean(const RenderResult& r, int x0, int y0, int w, int h) {
    double sum = 0, var = 0;
    for (int y = y0; y < y0 + h; ++y)
        for (int x = x0; x < x0 + w; ++x) {
            sum += luminance(r.image.at(x, y));
            var += luminanceVariance(r.variance.at(x, y));  // channels of a path taken as fully correlated
        }
    const double n = static_cast<double>(w) * h;
    return {sum / n, std::sqrt(var) / n, static_cast<std::size_t>(n)};
}

}  // namespace

// The closed furnace: every estimator, with and without light sampling, against the exact radiance;
// the error bar from 8 repeats with independent seeds (t against the 4-sigma tail, 7 degrees of freedom).
TEST(Furnace, ClosedSphereGivesLeOverOneMinusAlbedo) {
    const double le = 1.0, albedo = 0.5;
    const Scene scene = test::makeFurnaceSphere(le, albedo);
    const Accel accel(scene);
    const double exact = le / (1.0 - albedo) - le * std::pow(albedo, 65) / (1.0 - albedo);  // depth 64 truncation
    constexpr int kRepeats = 8;
    for (const std::string& name : estimatorNames())
        for (bool nee : {true, false}) {
            if (name == "paper") continue;  // biased on purpose; see the paper tests
            std::vector<double> means;
            for (int r = 0; r < kRepeats; ++r) {
                const RenderResult img = test::renderTiny(scene, name, 8, 32, mixSeed(42, r), 0, nee, 64);
                EXPECT_EQ(img.stats.badSamples, 0u);
                means.push_back(blockMean(img, 0, 0, 8, 8).mean);
            }
            const auto m = test::meanAndError(means);
            const double t = std::abs(m.mean - exact) / std::max(m.stdError, 1e-12);
            // A zero-variance estimator (symmetric on a diffuse furnace) must be exact to round-off.
            if (m.stdError < 1e-12)
                EXPECT_NEAR(m.mean, exact, 1e-9) << name;
            else
                EXPECT_LT(t, studentCritical(kRepeats - 1))
                    << name << (nee ? " with" : " without") << " light sampling: " << m.mean << " against " << exact;
        }
}

TEST(Furnace, CameraSeesEmissionOnlyAtDepthZero) {
    const Scene scene = test::makeFurnaceSphere(1.0, 0.5);
    const RenderResult r = test::renderTiny(scene, "cosine", 4, 4, 1, 0, true, 0);
    for (const Color& c : r.image.pixels) EXPECT_DOUBLE_EQ(c.x, 1.0);
}

namespace {

RenderResult renderWith(const Scene& scene, const Accel& accel, const Estimator& est, const std::string& sampler, int size,
                        std::uint32_t spp, std::uint64_t seed, int threads, bool nee, const TraceSettings& trace = {}) {
    RenderSettings rs;
    rs.trace = trace;
    rs.width = rs.height = size;
    rs.spp = spp;
    rs.seed = seed;
    rs.sampler = sampler;
    rs.threads = threads;
    rs.trace.nextEvent = nee;
    return render(scene, accel, est, rs);
}

/// Per-block means of R renders with independent seeds: the error bar of a block's mean comes from
/// the spread of the repeats (never from the renderer's own per-pixel variance, which is wrong for
/// stratified and low-discrepancy samples).
struct RepeatedBlocks {
    std::vector<std::vector<double>> blocks;  ///< [block][repeat] mean luminance; block 0 the whole image
};

RepeatedBlocks repeatedBlocks(const Scene& scene, const Accel& accel, const Estimator& est, const std::string& sampler, int size,
                              std::uint32_t spp, int repeats, std::uint64_t seed, double scale = 1.0, bool nee = true,
                              const TraceSettings& trace = {}) {
    const int b = 8, nb = (size / b) * (size / b);
    RepeatedBlocks out;
    out.blocks.assign(1 + nb, {});
    for (int r = 0; r < repeats; ++r) {
        const RenderResult img = renderWith(scene, accel, est, sampler, size, spp, mixSeed(seed, r), 0, nee, trace);
        out.blocks[0].push_back(scale * blockMean(img, 0, 0, size, size).mean);
        for (int by = 0; by < size / b; ++by)
            for (int bx = 0; bx < size / b; ++bx)
                out.blocks[1 + by * (size / b) + bx].push_back(scale * blockMean(img, bx * b, by * b, b, b).mean);
    }
    return out;
}

/// Largest |t| (Welch) between two sets of repeated blocks, and the critical value at the 4-sigma tail
/// for the smaller degrees of freedom.
double worstT(const RepeatedBlocks& a, const RepeatedBlocks& b, std::string& where) {
    double worst = 0;
    for (std::size_t k = 0; k < a.blocks.size(); ++k) {
        const auto ma = test::meanAndError(a.blocks[k]), mb = test::meanAndError(b.blocks[k]);
        const double se = std::sqrt(ma.stdError * ma.stdError + mb.stdError * mb.stdError);
        const double t = se > 0 ? std::abs(ma.mean - mb.mean) / se : 0.0;
        if (t > worst) {
            worst = t;
            where = k == 0 ? std::string("whole image") : fmt::format("block {}", k - 1);
        }
    }
    return worst;
}

}  // namespace

// Agreement of mean images on a 32x32 Cornell box. Error bars come from repeats with independent seeds
// (Welch t against the 4-sigma tail of Student's t), never from the renderer's own variance, which is
// wrong for low-discrepancy samples; the last test checks that the comparison catches a 1% bias.
class CornellAgreement : public ::testing::Test {
protected:
    static constexpr int kRepeats = 12, kSize = 32;
    static constexpr std::uint32_t kSpp = 128;  ///< per repeat, for the one-direction estimators
    static void SetUpTestSuite() {
        scene_ = new Scene(loadScene("cornell"));
        accel_ = new Accel(*scene_);
        const auto phong = makeEstimator("phong");
        reference_ = new RepeatedBlocks(repeatedBlocks(*scene_, *accel_, *phong, "sobol", kSize, 512, kRepeats, 2024));
    }
    static void TearDownTestSuite() {
        delete reference_;
        delete accel_;
        delete scene_;
    }
    /// Largest |t| of `name` (its own repeats) against the phong reference.
    static double against(const Estimator& est, std::uint32_t spp, std::uint64_t seed, std::string& where, double scale = 1.0,
                          bool nee = true, const TraceSettings& trace = {}) {
        return worstT(repeatedBlocks(*scene_, *accel_, est, "sobol", kSize, spp, kRepeats, seed, scale, nee, trace), *reference_, where);
    }
    static double critical() { return studentCritical(2 * kRepeats - 2); }
    static Scene* scene_;
    static Accel* accel_;
    static RepeatedBlocks* reference_;
};
Scene* CornellAgreement::scene_ = nullptr;
Accel* CornellAgreement::accel_ = nullptr;
RepeatedBlocks* CornellAgreement::reference_ = nullptr;

TEST_F(CornellAgreement, AllEstimatorsGiveTheSameMeanImage) {
    for (const std::string& name : estimatorNames()) {
        if (name == "paper") continue;  // biased on purpose: see below
        const auto est = makeEstimator(name);
        const std::uint32_t spp = est->returnsSets() ? 8 : kSpp;  // a set traces 16 to 24 paths per sample
        std::string where;
        const double t = against(*est, spp, 7, where);
        std::printf("%s vs phong: largest |t| = %.2f (%s), critical %.2f\n", name.c_str(), t, where.c_str(), critical());
        EXPECT_LT(t, critical()) << name << " vs phong at " << where;
    }
}

// symmetric-mix in both modes and with the paper's full orbit, first-hit splitting (phong and
// symmetric-mix), the joint 4D pattern and another first-bounce stream: the same mean image as phong.
TEST_F(CornellAgreement, SymmetricMixSplittingAndTheFirstBounceOptionsKeepTheMeanImage) {
    struct Case {
        const char* what;
        std::string estimator;
        SymmetricMode mode;
        int orbit, split;
        bool joint;
        std::uint32_t stream;
    };
    const Case cases[] = {{"symmetric-mix spread, orbit 2", "symmetric-mix", SymmetricMode::Spread, 2, 1, false, 0},
                          {"symmetric-mix spread, orbit 8", "symmetric-mix", SymmetricMode::Spread, 8, 1, false, 0},
                          {"symmetric-mix branch, orbit 8", "symmetric-mix", SymmetricMode::Branch, 8, 1, false, 0},
                          {"symmetric-mix spread, split 3", "symmetric-mix", SymmetricMode::Spread, 2, 3, false, 0},
                          {"phong, split 2", "phong", SymmetricMode::Branch, 2, 2, false, 0},
                          {"phong, joint 4D pattern", "phong", SymmetricMode::Branch, 2, 1, true, 0},
                          {"cosine, first-bounce stream 5", "cosine", SymmetricMode::Branch, 2, 1, false, 5}};
    for (const Case& c : cases) {
        EstimatorOptions o;
        o.symmetricMode = c.mode;
        o.symmetricOrbit = c.orbit;
        const auto est = makeEstimator(c.estimator, o);
        TraceSettings trace;
        trace.firstHitSplit = c.split;
        trace.jointFirstBounce = c.joint;
        trace.firstBounceStream = c.stream;
        const std::uint32_t spp =
            std::max<std::uint32_t>(8, kSpp / static_cast<std::uint32_t>(c.split * (est->returnsSets() ? c.orbit : 1)));
        std::string where;
        const double t = against(*est, spp, 31, where, 1.0, true, trace);
        std::printf("%s vs phong: largest |t| = %.2f (%s), critical %.2f\n", c.what, t, where.c_str(), critical());
        EXPECT_LT(t, critical()) << c.what << " vs phong at " << where;
    }
}

TEST_F(CornellAgreement, WithoutLightSamplingTheImageIsTheSame) {
    const auto phong = makeEstimator("phong");
    std::string where;
    const double t = against(*phong, 2 * kSpp, 99, where, 1.0, false);
    EXPECT_LT(t, critical()) << "no NEE vs NEE at " << where;
}

// The paper's estimator, as printed, renders a measurably darker box (its diffuse part is 14x low).
TEST_F(CornellAgreement, PaperImageIsMeasurablyBiased) {
    const auto paper = makeEstimator("paper");
    const RepeatedBlocks r = repeatedBlocks(*scene_, *accel_, *paper, "sobol", kSize, 2, kRepeats, 11);
    std::string where;
    const double t = worstT(r, *reference_, where);
    const double paperMean = test::meanAndError(r.blocks[0]).mean, refMean = test::meanAndError(reference_->blocks[0]).mean;
    std::printf("paper vs phong: largest |t| = %.1f (%s); image mean %.4f vs %.4f\n", t, where.c_str(), paperMean, refMean);
    EXPECT_GT(t, 3 * critical());
    EXPECT_LT(paperMean, 0.8 * refMean);
}

// The comparison above must be able to fail: an image 1% brighter or darker is caught at the same
// samples per pixel and repeats.
TEST_F(CornellAgreement, ComparisonDetectsAOnePercentBias) {
    const auto phong = makeEstimator("phong");
    for (double scale : {1.01, 0.99}) {
        std::string where;
        const double t = against(*phong, kSpp, 8, where, scale);
        std::printf("phong x %.2f vs phong: largest |t| = %.2f (%s)\n", scale, t, where.c_str());
        EXPECT_GT(t, critical()) << "a " << scale << " bias must be detected";
    }
}

namespace {

/// Every estimator under every sampler it can run under, the set estimators in both modes.
std::vector<std::pair<std::string, EstimatorOptions>> everyConfiguration(std::vector<std::string>& samplers) {
    std::vector<std::pair<std::string, EstimatorOptions>> out;
    for (const auto& e : estimatorNames())
        for (SymmetricMode mode : {SymmetricMode::Branch, SymmetricMode::Spread}) {
            if (!hasSymmetricModes(e) && mode == SymmetricMode::Spread) continue;
            EstimatorOptions o;
            o.symmetricMode = mode;
            out.push_back({e, o});
        }
    samplers = samplerNames();
    return out;
}

bool sameBits(const Image& a, const Image& b) {
    return a.pixels.size() == b.pixels.size() && std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(Color)) == 0;
}

}  // namespace

// Item 2 of the sampling issue: image, variance and statistics are the same bit for bit at 1, 2 and 7
// threads, for every estimator x sampler (and mode), with and without NEE, on an image of 9 tiles (some
// partial); a different seed changes the image.
TEST(Determinism, SameSeedSameImageAtAnyThreadCountForEverySampler) {
    const Scene scene = loadScene("cornell");
    const Accel accel(scene);
    std::vector<std::string> samplers;
    for (const auto& [name, options] : everyConfiguration(samplers)) {
        const auto est = makeEstimator(name, options);
        for (const std::string& sampler : samplers) {
            if (!est->requiredSampler().empty() && sampler != samplers.front()) continue;
            for (bool nee : {true, false}) {
                const std::string what =
                    fmt::format("{} ({}) under {}, NEE {}", name, symmetricModeName(options.symmetricMode), sampler, nee);
                const RenderResult one = renderWith(scene, accel, *est, sampler, 40, 3, 5, 1, nee);
                for (int threads : {2, 7}) {
                    const RenderResult many = renderWith(scene, accel, *est, sampler, 40, 3, 5, threads, nee);
                    EXPECT_TRUE(sameBits(one.image, many.image)) << what << ", " << threads << " threads: image";
                    EXPECT_TRUE(sameBits(one.variance, many.variance)) << what << ", " << threads << " threads: variance";
                    EXPECT_EQ(one.stats.rays, many.stats.rays) << what << ", " << threads << " threads";
                    EXPECT_EQ(one.stats.badSamples, many.stats.badSamples) << what;
                }
                const RenderResult other = renderWith(scene, accel, *est, sampler, 40, 3, 6, 2, nee);
                EXPECT_FALSE(sameBits(one.image, other.image)) << what << ": a different seed must give a different image";
            }
        }
    }
}

// Item 6: the mean image of every sampler agrees with `independent` (phong), and spread mode with
// branch mode and with phong; error bars from 12 repeats each (Welch t, 22 degrees of freedom, critical
// value at the 4-sigma tail). A power check: the same comparison catches a 3% brighter image (whole-image t about 8).
TEST(SamplerAgreement, MeanImagesAgreeWithIndependent) {
    const Scene scene = loadScene("cornell");
    const Accel accel(scene);
    constexpr int kRepeats = 12, kSize = 32;
    const double critical = studentCritical(2 * kRepeats - 2);
    const auto phong = makeEstimator("phong");
    const RepeatedBlocks reference = repeatedBlocks(scene, accel, *phong, "independent", kSize, 128, kRepeats, 100);
    std::string where;
    for (const char* sampler : {"stratified", "sobol"}) {
        const RepeatedBlocks r = repeatedBlocks(scene, accel, *phong, sampler, kSize, 64, kRepeats, 200);
        const double t = worstT(r, reference, where);
        std::printf("phong under %s vs independent: largest |t| = %.2f (%s), critical %.2f\n", sampler, t, where.c_str(), critical);
        EXPECT_LT(t, critical) << sampler << " at " << where;
    }
    for (const char* name : {"symmetric", "symmetric-shifted"}) {
        EstimatorOptions o;
        o.symmetricMode = SymmetricMode::Spread;
        const auto spread = makeEstimator(name, o);
        const RepeatedBlocks r = repeatedBlocks(scene, accel, *spread, "sobol", kSize, 48, kRepeats, 300);
        const double t = worstT(r, reference, where);
        std::printf("%s spread under sobol vs phong: largest |t| = %.2f (%s)\n", name, t, where.c_str());
        EXPECT_LT(t, critical) << name << " spread at " << where;
    }
    const RepeatedBlocks brighter = repeatedBlocks(scene, accel, *phong, "sobol", kSize, 64, kRepeats, 400, 1.03);
    const double t = worstT(brighter, reference, where);
    std::printf("3%% brighter sobol vs independent: largest |t| = %.2f (%s)\n", t, where.c_str());
    EXPECT_GT(t, critical) << "the comparison must detect a 3% bias";
}

// Every bundled scene (the built-in box, scenes/*.json, the shared OBJ scenes) with every estimator:
// no NaN, no negative pixel, no discarded sample.
TEST(Render, NoPixelIsNaNOnAnyBundledScene) {
    std::vector<std::string> scenes = {"cornell"};
    for (const auto& e : std::filesystem::directory_iterator(std::filesystem::path(SYMPHONG_SOURCE_DIR) / "scenes"))
        if (e.path().extension() == ".json" && (e.path().filename() != "mcguire-glossy.json" || !test::scenesDir().empty()))
            scenes.push_back(e.path().string());
    if (!test::scenesDir().empty())
        for (const char* rel :
             {"cornell-box-mcguire/CornellBox-Sphere.obj", "cornell-box-original/cornell_box.obj", "bunny/stanford-bunny.obj"})
            scenes.push_back(test::scenesDir() + "/" + rel);
    EXPECT_GE(scenes.size(), 6u);
    for (const std::string& spec : scenes) {
        const Scene scene = loadScene(spec);
        for (const std::string& name : estimatorNames()) {
            const RenderResult r = test::renderTiny(scene, name, 12, 2, 3);
            EXPECT_EQ(r.stats.badSamples, 0u) << spec << " " << name;
            for (const Color& c : r.image.pixels) ASSERT_TRUE(isFinite(c) && minComponent(c) >= 0) << spec << " " << name;
        }
    }
}

// Cancellation is deterministic through the tile hook: cancelled after k finished tiles, a one-thread
// render stops with exactly k tiles drawn; with more threads, at most the tiles already in flight
// finish too.
// Splitting is k calls on the sub-samples of the pixel's pattern: the first hit of a camera sample traces
// k paths (k times the rays of its continuations), and k = 1 is the unsplit render bit for bit. The
// first-bounce stream 0 is the render's own numbers; another stream changes the image but nothing else of
// a render that never reaches a first bounce (max depth 0).
TEST(Render, SplittingAndFirstBounceStreamsDoWhatTheySay) {
    const Scene scene = loadScene("cornell");
    const Accel accel(scene);
    const auto phong = makeEstimator("phong");
    TraceSettings one, two, stream;
    one.firstHitSplit = 1;
    two.firstHitSplit = 2;
    const RenderResult a = renderWith(scene, accel, *phong, "sobol", 24, 4, 3, 0, true);
    const RenderResult b = renderWith(scene, accel, *phong, "sobol", 24, 4, 3, 0, true, one);
    EXPECT_TRUE(sameBits(a.image, b.image));
    // A library caller's k below 1 (the command line refuses it) is k = 1: one call, its light sample
    // weighed against one call's pdf, in either tracer.
    for (const int k : {0, -3})
        for (const TracerChoice tracer : {TracerChoice::Recursive, TracerChoice::Wavefront}) {
            TraceSettings below;
            below.firstHitSplit = k, below.tracer = tracer;
            EXPECT_TRUE(sameBits(a.image, renderWith(scene, accel, *phong, "sobol", 24, 4, 3, 0, true, below).image))
                << "k = " << k << ", tracer " << static_cast<int>(tracer);
        }
    TraceSettings noRoulette;
    noRoulette.maxDepth = 1;
    noRoulette.nextEvent = false;
    TraceSettings noRoulette2 = noRoulette;
    noRoulette2.firstHitSplit = 2;
    const RenderResult c = renderWith(scene, accel, *phong, "sobol", 24, 4, 3, 0, false, noRoulette);
    const RenderResult d = renderWith(scene, accel, *phong, "sobol", 24, 4, 3, 0, false, noRoulette2);
    // Depth 1, no NEE: camera rays plus one ray per first-hit direction (two when split), none dropped
    // below the surface more often than the other by more than a few percent.
    const double extraUnsplit = static_cast<double>(c.stats.rays - c.stats.samples),
                 extraSplit = static_cast<double>(d.stats.rays - d.stats.samples);
    EXPECT_NEAR(extraSplit / extraUnsplit, 2.0, 0.1);
    stream.firstBounceStream = 0;
    EXPECT_TRUE(sameBits(a.image, renderWith(scene, accel, *phong, "sobol", 24, 4, 3, 0, true, stream).image));
    stream.firstBounceStream = 1;
    EXPECT_FALSE(sameBits(a.image, renderWith(scene, accel, *phong, "sobol", 24, 4, 3, 0, true, stream).image));
    TraceSettings depth0 = stream;
    depth0.maxDepth = 0;
    TraceSettings depth0own;
    depth0own.maxDepth = 0;
    EXPECT_TRUE(sameBits(renderWith(scene, accel, *phong, "sobol", 24, 4, 3, 0, true, depth0own).image,
                         renderWith(scene, accel, *phong, "sobol", 24, 4, 3, 0, true, depth0).image));
}

// The variance budget against independent values: (1) a zero-variance first bounce (cosine sampling of a
// diffuse sphere inside a uniformly emitting sphere, depth 1, no NEE: every direction weighs rho_d and
// sees Le) gives a first-bounce variance of exactly 0; uniform sampling there gives a positive one, equal
// to the whole pixel variance (the pixel position does not matter inside the sphere: every pixel sees
// the same radiance), within the sampling error of 8 pairs.
TEST(Render, VarianceBudgetMatchesClosedFormsOnTheFurnace) {
    const Scene scene = test::makeFurnaceSphere(1.0, 0.5);
    const Accel accel(scene);
    TraceSettings t1, t2;
    t1.maxDepth = t2.maxDepth = 1;
    t1.nextEvent = t2.nextEvent = false;
    t1.firstBounceStream = 1;
    t2.firstBounceStream = 2;
    const auto cosine = makeEstimator("cosine"), uniform = makeEstimator("uniform");
    const RenderResult c1 = renderWith(scene, accel, *cosine, "sobol", 8, 4, 9, 0, false, t1);
    const RenderResult c2 = renderWith(scene, accel, *cosine, "sobol", 8, 4, 9, 0, false, t2);
    EXPECT_NEAR(halfSquaredDifference(c1.image, c2.image), 0.0, 1e-24);
    std::vector<double> budget, total;
    std::vector<Image> images;
    for (int pair = 0; pair < 8; ++pair) {
        const RenderResult u1 = renderWith(scene, accel, *uniform, "independent", 8, 4, 100 + pair, 0, false, t1);
        const RenderResult u2 = renderWith(scene, accel, *uniform, "independent", 8, 4, 100 + pair, 0, false, t2);
        budget.push_back(halfSquaredDifference(u1.image, u2.image));
        images.push_back(u1.image);
    }
    std::vector<const Image*> ptrs;
    for (const Image& im : images) ptrs.push_back(&im);
    const double pixelVariance = pixelVarianceAcrossRepeats(ptrs);
    const auto b = test::meanAndError(budget);
    EXPECT_GT(b.mean, 0.0);
    // Each figure has about 64 pixels x 8 pairs of chi-square terms: agreement within 25%.
    EXPECT_NEAR(b.mean / pixelVariance, 1.0, 0.25) << b.mean << " vs " << pixelVariance;
}

// Next-event estimation's MIS weight (render/path_tracer.h DirectLight::value) against the power heuristic
// by hand: f L cos w / p with w = p^2 / (p^2 + (k p_e)^2); nothing (a light sample that did not arrive) is an
// exact +0 whatever k; a delta emitter's contribution is not weighed.
TEST(Render, DirectLightValueIsThePowerHeuristicsWeight) {
    const auto expectColor = [](const Color& got, const Color& want) {
        EXPECT_DOUBLE_EQ(got.x, want.x);
        EXPECT_DOUBLE_EQ(got.y, want.y);
        EXPECT_DOUBLE_EQ(got.z, want.z);
    };
    for (const double k : {0.0, 1.0, 8.0}) {
        const Color zero = DirectLight{}.value(k);
        for (int i = 0; i < 3; ++i) EXPECT_FALSE(std::signbit(zero[i]) || zero[i] != 0) << k;
    }
    DirectLight d;
    d.unweighted = Color(1, 2, 3), d.cosine = 0.5, d.lightPdf = 2, d.estimatorPdf = 2;
    expectColor(d.value(1), Color(1, 2, 3) * (0.5 * (4.0 / 8.0) / 2));   // w = 4 / (4 + 4)
    expectColor(d.value(3), Color(1, 2, 3) * (0.5 * (4.0 / 40.0) / 2));  // w = 4 / (4 + 36)
    expectColor(d.value(0), Color(1, 2, 3) * (0.5 / 2));                 // no estimator calls: w = 1
    d.estimatorPdf = 0;
    expectColor(d.value(5), Color(1, 2, 3) * (0.5 / 2));  // a direction the estimator never takes
    DirectLight point;
    point.unweighted = Color(4, 5, 6), point.delta = true;
    expectColor(point.value(7), Color(4, 5, 6));
}

TEST(Render, CancellingAfterKTilesStopsThere) {
    const Scene scene = loadScene("cornell");
    const Accel accel(scene);
    const auto est = makeEstimator("cosine");
    for (int threads : {1, 2}) {
        std::atomic<bool> cancel{false};
        std::atomic<int> tiles{0};
        RenderSettings rs;
        rs.width = rs.height = 64;  // 16 tiles of 16 x 16
        rs.spp = 2;
        rs.threads = threads;
        rs.cancel = &cancel;
        rs.onTileDone = [&] {
            if (++tiles == 3) cancel = true;
        };
        const RenderResult r = render(scene, accel, *est, rs);
        EXPECT_TRUE(r.cancelled);
        int drawn = 0;
        for (int ty = 0; ty < 4; ++ty)
            for (int tx = 0; tx < 4; ++tx) {
                bool any = false;
                for (int y = ty * 16; y < ty * 16 + 16; ++y)
                    for (int x = tx * 16; x < tx * 16 + 16; ++x) any = any || maxComponent(r.image.at(x, y)) > 0;
                drawn += any;
            }
        EXPECT_EQ(drawn, tiles.load()) << "every finished tile is drawn, no other";
        if (threads == 1)
            EXPECT_EQ(drawn, 3);
        else
            EXPECT_LE(drawn, 3 + threads - 1);
    }
}

namespace {

/// A quad (two triangles) with corners a, b, c, d counter-clockwise as seen from the side it faces.
using test::addQuad;

/// Material 0 emits Le = 1 (and reflects nothing); material 1 is white diffuse.
Scene emitterScene() {
    Scene s;
    PhongMaterial light;
    light.name = "light";
    light.rhoD = Color(0.0);
    light.emission = Color(1.0);
    PhongMaterial white;
    white.name = "white";
    white.rhoD = Color(0.8);
    s.materials = {light, white};
    s.camera.position = Vec3(0, 0, 0);
    s.camera.target = Vec3(0, 0, -1);
    s.camera.up = Vec3(0, 1, 0);
    s.camera.fovY = 90;
    return s;
}

double imageMean(const Image& img) {
    double sum = 0;
    for (const Color& c : img.pixels) sum += luminance(c);
    return sum / static_cast<double>(img.pixels.size());
}

}  // namespace

// Emitters are one-sided: seen from behind, and lighting a floor they face away from, they give nothing;
// turned around, the same geometry lights the camera and the floor. Every estimator, with and without
// light sampling.
TEST(Emitters, EmitFromTheirFrontSideOnly) {
    for (bool facing : {false, true}) {
        // A light square in front of the camera, tilted so that its front faces both the camera and the
        // floor below it (facing), or wound the other way round so that both see its back.
        Scene s = emitterScene();
        const Vec3 a(-1, -0.2, -2.6), b(1, -0.2, -2.6), c(1, 1, -2), d(-1, 1, -2);  // normal (0, -0.45, 0.89)
        if (facing)
            addQuad(s, a, b, c, d, 0);
        else
            addQuad(s, a, d, c, b, 0);  // the same square wound the other way: normal away from camera and floor
        // The floor, normal +y, ends in front of the light (z >= -2): all of it sees the light's back
        // when the light is turned away (beyond the light, in -z, the floor would see its front).
        addQuad(s, Vec3(-5, -1, 1), Vec3(5, -1, 1), Vec3(5, -1, -2), Vec3(-5, -1, -2), 1);
        for (const std::string& name : estimatorNames())
            for (bool nee : {true, false}) {
                const RenderResult r = test::renderTiny(s, name, 16, 8, 3, 0, nee, 4);
                // The floor region below the light: the bottom rows of the image.
                double floorLight = 0;
                for (int y = 12; y < 16; ++y)
                    for (int x = 0; x < 16; ++x) floorLight += luminance(r.image.at(x, y));
                if (facing) {
                    EXPECT_GT(imageMean(r.image), 0.05) << name << (nee ? " with" : " without") << " NEE";
                    EXPECT_GT(floorLight, 0) << name << (nee ? " with" : " without") << " NEE";
                } else {
                    EXPECT_EQ(imageMean(r.image), 0.0) << name << (nee ? " with" : " without") << " NEE: light from an emitter's back";
                }
            }
    }
}

// Camera geometry: with a 90-degree field of view, an emitter covering exactly the half-plane x < 0 at
// depth 1 fills the left half of an even-width image: the left columns are fully lit (Le on every
// sample), the right ones black; the same for y and the top rows. A half-pixel shift of the rays, or
// a flipped axis, moves the edge into a column.
TEST(Camera, ImageEdgesLandOnPixelEdges) {
    for (bool vertical : {false, true}) {
        Scene s = emitterScene();
        if (!vertical)
            addQuad(s, Vec3(-10, -10, -1), Vec3(0, -10, -1), Vec3(0, 10, -1), Vec3(-10, 10, -1), 0);  // x < 0
        else
            addQuad(s, Vec3(-10, 0, -1), Vec3(10, 0, -1), Vec3(10, 10, -1), Vec3(-10, 10, -1), 0);  // y > 0: top
        for (const char* sampler : {"independent", "sobol"}) {
            const auto est = makeEstimator("cosine");
            RenderSettings rs;
            rs.width = 8;
            rs.height = 6;
            rs.spp = 64;
            rs.sampler = sampler;
            rs.trace.maxDepth = 0;
            const Accel accel(s);
            const RenderResult r = render(s, accel, *est, rs);
            for (int y = 0; y < rs.height; ++y)
                for (int x = 0; x < rs.width; ++x) {
                    const bool lit = vertical ? y < rs.height / 2 : x < rs.width / 2;
                    EXPECT_EQ(r.image.at(x, y).x, lit ? 1.0 : 0.0)
                        << sampler << (vertical ? " top half" : " left half") << ": pixel (" << x << ", " << y << ")";
                }
        }
    }
}

// A pixel's camera rays go to Embree as one coherent packet (PathTracer::cameraRadiances): each sample's
// radiance must be the one cameraRadiance gives for the same sample traced alone (the second method: one
// rtcIntersect1 per camera ray). Packet kernels may round differently from the single-ray one on another
// CPU, so a value may differ by round-off there; on any CPU nearly every sample is equal to 1e-9, and a
// packet that mixed up its streams, rays or order would differ everywhere.
TEST(Render, CameraPacketsTraceWhatSingleCameraRaysTrace) {
    std::vector<std::string> scenes = {"cornell", std::string(SYMPHONG_SOURCE_DIR) + "/scenes/cornell-glossy-100.json"};
    if (!test::scenesDir().empty()) scenes.push_back(test::scenesDir() + "/bunny/stanford-bunny.obj");
    for (const std::string& spec : scenes) {
        const Scene scene = loadScene(spec);
        const Accel accel(scene);
        const auto estimator = makeEstimator("phong");
        const PathTracer tracer(scene, accel, *estimator, TraceSettings{});
        const int width = 24, height = 18;
        const std::uint32_t spp = 40;  // packets of 16, 16 and 8 a pixel
        const auto sampler = makeSampler("sobol", spp, 7);
        const CameraRays cameraRays(scene.camera, width, height);
        PathScratch scratch;
        TraceStats packetStats, singleStats;
        std::size_t compared = 0, differing = 0, lit = 0;
        for (int y = 0; y < height; y += 5)
            for (int x = 0; x < width; x += 3) {
                const std::size_t pixel = static_cast<std::size_t>(y) * width + x;
                for (std::uint32_t first = 0; first < spp; first += PathTracer::kCameraPacket) {
                    const std::size_t n = std::min<std::size_t>(PathTracer::kCameraPacket, spp - first);
                    std::array<SampleStream, PathTracer::kCameraPacket> streams;
                    std::array<Vec3, PathTracer::kCameraPacket> dirs;
                    std::array<Color, PathTracer::kCameraPacket> packet;
                    Vec3 o;
                    for (std::size_t k = 0; k < n; ++k) {
                        streams[k] = SampleStream(*sampler, pixel, first + static_cast<std::uint32_t>(k), SampleDimensions::kPixel);
                        const Point2 jitter = streams[k].get2D();
                        cameraRays(x + jitter.u, y + jitter.v, o, dirs[k]);
                    }
                    tracer.cameraRadiances(o, dirs.data(), n, streams.data(), packet.data(), packetStats, scratch);
                    for (std::size_t k = 0; k < n; ++k) {
                        SampleStream alone(*sampler, pixel, first + static_cast<std::uint32_t>(k), SampleDimensions::kPixel);
                        const Point2 jitter = alone.get2D();
                        Vec3 so, sd;
                        cameraRays(x + jitter.u, y + jitter.v, so, sd);
                        const Color single = tracer.cameraRadiance(so, sd, alone, singleStats, scratch);
                        ++compared;
                        lit += luminance(single) > 0;
                        const double scale = std::max(1e-30, maxComponent(single));
                        const Vec3 d = packet[k] - single;
                        if (std::max({std::abs(d.x), std::abs(d.y), std::abs(d.z)}) > 1e-9 * scale) ++differing;
                    }
                }
            }
        EXPECT_GT(lit, compared / 2) << spec;  // the comparison saw light
        EXPECT_LE(differing, compared / 100) << spec << ": " << differing << " of " << compared << " camera samples differ";
        EXPECT_NEAR(static_cast<double>(packetStats.rays), static_cast<double>(singleStats.rays), 0.01 * singleStats.rays) << spec;
    }
}

// The render loop gathers a tile's camera samples into packets that span pixels when a pixel takes fewer
// samples than a packet holds (here 5 a pixel: a packet of 16 holds parts of four pixels). Its image must
// be the mean that each sample traced alone gives (cameraRadiance, one rtcIntersect1 per camera ray),
// pixel by pixel: samples given to the wrong pixel, dropped at a tile's end or added twice would move it.
TEST(Render, PacketsThatSpanPixelsGiveEachPixelItsOwnSamples) {
    const Scene scene = loadScene("cornell");
    const Accel accel(scene);
    const auto estimator = makeEstimator("phong");
    // 21 x 19 pixels: tiles of 16 x 16, 5 x 16, 16 x 3 and 5 x 3; at 1 sample a pixel the last tile's 15
    // samples fill no packet (they go at its end), at 5 a packet holds parts of four pixels.
    for (const std::uint32_t spp : {1u, 5u}) {
        RenderSettings rs;
        rs.width = 21;
        rs.height = 19;
        rs.spp = spp;
        rs.sampler = "sobol";
        rs.seed = 3;
        const RenderResult r = render(scene, accel, *estimator, rs);
        const PathTracer tracer(scene, accel, *estimator, rs.trace);
        const auto sampler = makeSampler("sobol", rs.spp, rs.seed);
        const CameraRays cameraRays(scene.camera, rs.width, rs.height);
        PathScratch scratch;
        TraceStats stats;
        std::size_t differing = 0, lit = 0;
        for (int y = 0; y < rs.height; ++y)
            for (int x = 0; x < rs.width; ++x) {
                const std::size_t pixel = static_cast<std::size_t>(y) * rs.width + x;
                Color sum(0.0);
                for (std::uint32_t i = 0; i < rs.spp; ++i) {
                    SampleStream samples(*sampler, pixel, i, SampleDimensions::kPixel);
                    const Point2 jitter = samples.get2D();
                    Vec3 o, d;
                    cameraRays(x + jitter.u, y + jitter.v, o, d);
                    sum += tracer.cameraRadiance(o, d, samples, stats, scratch);
                }
                const Color mean = sum / static_cast<double>(rs.spp), got = r.image.at(x, y);
                lit += luminance(mean) > 0;
                const Vec3 diff = got - mean;
                if (std::max({std::abs(diff.x), std::abs(diff.y), std::abs(diff.z)}) > 1e-9 * std::max(1e-30, maxComponent(mean))) ++differing;
            }
        const std::size_t pixels = static_cast<std::size_t>(rs.width) * rs.height;
        EXPECT_GT(lit, pixels / 2) << spp << " spp";
        // None differs here; one is allowed for a CPU whose packet kernel answers a grazing camera ray otherwise.
        EXPECT_LE(differing, 1u) << spp << " spp: " << differing << " of " << pixels << " pixels differ from their samples traced alone";
        EXPECT_NEAR(static_cast<double>(r.stats.rays), static_cast<double>(stats.rays), 0.005 * static_cast<double>(stats.rays)) << spp << " spp";
    }
}
