// `symphong study`: metrics on synthetic images with known error, the bias flag on a tiny scene
// (fires for `paper`, not for `cosine`), the CSV/JSON schema, the plots, the reference cache and Ctrl-C.
#include "accel/accel.h"
#include "answer_factors.h"
#include "cli/cli.h"
#include "compare/metrics.h"
#include "estimators/registry.h"
#include "io/files.h"
#include "io/image.h"
#include "io/input_error.h"
#include "render/renderer.h"
#include "scene/scene.h"
#include "splitting/learning.h"
#include "study/comparisons.h"
#include "study/study.h"
#include "study/study_parts.h"
#include "test_util.h"
#include "util/cpu_time.h"

#include <fmt/format.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <csignal>
#include <ctime>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>
#include <thread>

#include <unistd.h>

using namespace symphong;
namespace fs = std::filesystem;

namespace {

Image constantImage(int w, int h, double v) {
    Image img(w, h);
    for (Color& c : img.pixels) c = Color(v);
    return img;
}

std::string readAll(const fs::path& p) { return readTextFile(p.string()); }

fs::path freshDir(const std::string& name) {
    // One directory per process: CTest runs the tests of this file as parallel processes.
    const fs::path d = fs::temp_directory_path() / ("symphong-study-" + name + "-" + std::to_string(::getpid()));
    fs::remove_all(d);
    return d;
}

StudyConfig tinyConfig(const fs::path& dir) {
    StudyConfig c;
    c.estimators = {"cosine", "phong", "paper"};
    c.spps = {16, 64};
    c.repeats = 2;
    c.width = c.height = 16;
    c.referenceSpp = 512;
    c.outDir = dir.string();
    c.plots = false;
    return c;
}

}  // namespace

// ----------------------------------------------------------------------------------------------------
// Metrics on images with known error

TEST(StudyMetrics, ErrorsOfAKnownPerturbation) {
    const Image ref = constantImage(8, 4, 0.5);
    Image img = ref;
    for (int i = 0; i < 32; ++i) img.pixels[i] += Color(i % 2 ? 0.1 : -0.1);  // +-0.1 in luminance
    const ImageError e = imageError(img, ref);
    EXPECT_NEAR(e.mse, 0.01, 1e-12);
    EXPECT_NEAR(e.rmse, 0.1, 1e-12);
    EXPECT_NEAR(e.relMse, 0.01 / (0.25 + 0.01), 1e-12);
    EXPECT_THROW(imageError(constantImage(2, 2, 0), ref), std::invalid_argument);
}

TEST(StudyMetrics, NoisyImagesAroundTheReference) {
    // Reference + Gaussian-like noise of known variance: the MSE estimate is within its sampling error.
    const int w = 200, h = 200;
    Image ref(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) ref.at(x, y) = Color(0.2 + 0.6 * x / w);
    Rng rng(3, 3);
    Image img = ref;
    const double sigma = 0.05;
    for (Color& c : img.pixels) {
        const double u1 = std::max(rng.uniform(), 1e-300), u2 = rng.uniform();
        c += Color(sigma * std::sqrt(-2 * std::log(u1)) * std::cos(kTwoPi * u2));
    }
    const ImageError e = imageError(img, ref);
    const double n = w * h, se = sigma * sigma * std::sqrt(2.0 / n);
    EXPECT_NEAR(e.mse, sigma * sigma, 4 * se);
}

// The reference's own error (Reference::noiseSd: the spread of its realized mean squared error, sqrt(2 sum_p
// sigma_p^4) / P for Gaussian pixel errors) against a second method. Pairs of independent references of the
// built-in box (the study's reference sampler, independent; seeds 1-96): the mean squared difference d of a
// pair, less its expectation (the two noises), spreads over the pairs as the same formula says for the
// difference of two (sqrt(2 sum_p (s1_p^2 + s2_p^2)^2) / P). The spread of 48 pairs must be within 0.7-1.4 of the
// prediction (its sampling error alone is about 10%; the pixel errors of a 256-sample mean are not quite Gaussian).
TEST(StudyReference, ItsOwnErrorSpreadsAsItsNoiseSdSays) {
    const Scene scene = loadScene("cornell");
    const Accel accel(scene);
    const auto est = makeEstimator("phong");
    StudyConfig c;
    RenderSettings rs;
    rs.width = 16, rs.height = 12, rs.spp = 256, rs.sampler = "independent", rs.threads = 2;
    const int pairs = 48;
    const double P = rs.width * rs.height;
    std::vector<double> excess;
    double predicted = 0;
    for (int k = 0; k < pairs; ++k) {
        rs.seed = 2 * k + 1;
        const RenderResult first = render(scene, accel, *est, rs);
        rs.seed = 2 * k + 2;
        const RenderResult second = render(scene, accel, *est, rs);
        const Reference r1 = referenceFromRender(c, first, rs.spp), r2 = referenceFromRender(c, second, rs.spp);
        double own = 0, fourth = 0, d = 0;
        for (std::size_t p = 0; p < first.variance.pixels.size(); ++p) {
            const double v1 = luminanceVariance(first.variance.pixels[p]), v2 = luminanceVariance(second.variance.pixels[p]);
            own += v1 * v1;
            fourth += (v1 + v2) * (v1 + v2);
            const double diff = luminance(r1.image.pixels[p]) - luminance(r2.image.pixels[p]);
            d += diff * diff / P;
        }
        ASSERT_GT(r1.noiseSd, 0);
        EXPECT_NEAR(r1.noiseSd, std::sqrt(2 * own) / P, 1e-12 * r1.noiseSd);  // its closed form
        excess.push_back(d - r1.noise - r2.noise);
        predicted += std::sqrt(2 * fourth) / P / pairs;
    }
    double mean = 0, ss = 0;
    for (double e : excess) mean += e / pairs;
    for (double e : excess) ss += (e - mean) * (e - mean);
    const double spread = std::sqrt(ss / (pairs - 1));
    std::printf("realized error of a pair of references: spread %.4g, predicted %.4g (ratio %.3f), mean %.3g\n", spread, predicted,
                spread / predicted, mean);
    EXPECT_GT(spread / predicted, 0.7);
    EXPECT_LT(spread / predicted, 1.4);
    EXPECT_NEAR(mean, 0.0, 4 * spread / std::sqrt(pairs));  // the noise removed is the error's mean
}

// A reference that splits (--reference-splitting ears) against a second method, a plain one: both are
// unbiased, so the mean squared difference d of an EARS reference and an independent plain one is, on
// average, the sum of their noises (each its pixels' variances over the samples, which under EARS come from
// epochs of different factors), with no bias term; over 24 pairs of the smooth-sky scene the mean of
// d - noise_ears - noise_plain must be within 4 standard errors of 0 (their spread over the pairs), and
// the EARS reference must split (more rays) and have the smaller noise (0.65 of the plain one's at equal spp
// on this 16 x 12 image; 0.21 at 128 x 96 and 1024 spp, where it has more to learn from).
// Only a reference that splits names its splitting in the cache's key: the caches of plain references
// made before the option keep theirs.
TEST(StudyReference, OneThatSplitsIsUnbiasedAndItsNoiseIsWhatItSays) {
    const Scene scene = loadScene(SYMPHONG_SOURCE_DIR "/scenes/regime/sky-n10.json");
    const Accel accel(scene);
    const auto est = makeEstimator("phong");
    StudyConfig c;
    EXPECT_FALSE(referenceKey(c).contains("splitting"));
    EXPECT_EQ(referenceMethod(c), "phong");
    c.referenceSplitting = "ears";
    EXPECT_EQ(referenceKey(c)["splitting"], "ears");
    EXPECT_EQ(referenceMethod(c), "phong+ears");
    RenderSettings rs;
    rs.width = 16, rs.height = 12, rs.spp = 256, rs.sampler = "independent", rs.threads = 2;
    const int pairs = 24;
    const double P = rs.width * rs.height;
    std::vector<double> excess;
    double earsNoise = 0, plainNoise = 0, earsRays = 0, plainRays = 0;
    for (int k = 0; k < pairs; ++k) {
        rs.seed = 2 * k + 1;
        rs.trace.splitting = SplittingMode::Ears;
        const RenderResult split = render(scene, accel, *est, rs);
        rs.seed = 2 * k + 2;
        rs.trace.splitting = SplittingMode::None;
        const RenderResult plain = render(scene, accel, *est, rs);
        const Reference r1 = referenceFromRender(c, split, rs.spp), r2 = referenceFromRender(c, plain, rs.spp);
        double d = 0;
        for (std::size_t p = 0; p < r1.image.pixels.size(); ++p) {
            const double diff = luminance(r1.image.pixels[p]) - luminance(r2.image.pixels[p]);
            d += diff * diff / P;
        }
        excess.push_back(d - r1.noise - r2.noise);
        earsNoise += r1.noise / pairs, plainNoise += r2.noise / pairs;
        earsRays += static_cast<double>(split.stats.rays), plainRays += static_cast<double>(plain.stats.rays);
    }
    double mean = 0, ss = 0;
    for (double e : excess) mean += e / pairs;
    for (double e : excess) ss += (e - mean) * (e - mean);
    const double standardError = std::sqrt(ss / (pairs - 1) / pairs);
    std::printf("EARS reference against a plain one: d - noises %.3g +- %.3g (noises %.3g and %.3g)\n", mean, standardError, earsNoise,
                plainNoise);
    EXPECT_NEAR(mean, 0.0, 4 * standardError);
    EXPECT_GT(earsRays, 1.2 * plainRays);
    EXPECT_LT(earsNoise, 0.85 * plainNoise);
}

// The report's words on the reference's noise: none while it is less than half of every MSE; where it is at
// least half of the least one, how much of it that MSE still shares after its removal (the standard deviation,
// and as a share of the MSE), which the intervals include; a warning above a tenth of the MSE.
TEST(StudyReference, TheReportSaysHowMuchOfItsNoiseEachMseShares) {
    std::vector<StudySummary> summary(2);
    summary[0].variant = "phong", summary[0].spp = 64, summary[0].mse = 1e-4;
    summary[1].variant = "phong+ears", summary[1].spp = 64, summary[1].mse = 2e-5;
    Reference ref;
    ref.noise = 9e-6, ref.noiseSd = 1e-7;
    EXPECT_EQ(referenceNoiseWords(summary, ref), "");
    ref.noise = 1e-5;  // half of phong+ears's MSE
    std::string words = referenceNoiseWords(summary, ref);
    EXPECT_EQ(words.rfind("The reference's own noise (1e-05) is at least half", 0), 0u) << words;
    EXPECT_NE(words.find("(`phong+ears` at 64 spp: 2e-05)"), std::string::npos) << words;
    EXPECT_NE(words.find("standard deviation 1e-07, 0.5% of that MSE"), std::string::npos) << words;
    EXPECT_NE(words.find("the efficiency intervals by MSE include it"), std::string::npos) << words;
    EXPECT_EQ(words.find("Warning"), std::string::npos) << words;
    ref.noiseSd = 4e-6;  // a fifth of that MSE
    words = referenceNoiseWords(summary, ref);
    EXPECT_EQ(words.rfind("**Warning:** the reference's own noise (1e-05)", 0), 0u) << words;
    EXPECT_NE(words.find("standard deviation 4e-06, 20.0% of that MSE"), std::string::npos) << words;
    EXPECT_NE(words.find("Raise --reference-spp, or render the reference with --reference-splitting ears where EARS splits."),
              std::string::npos)
        << words;
}

TEST(StudyMetrics, MeanLuminanceAndItsError) {
    const Image img = constantImage(10, 10, 0.3);
    const Image var = constantImage(10, 10, 0.04);  // each pixel mean has standard deviation 0.2
    const MeanWithError m = meanLuminance(img, &var);
    EXPECT_NEAR(m.mean, 0.3, 1e-12);
    EXPECT_NEAR(m.stdError, 0.2 / 10.0, 1e-12);  // sqrt(100 * 0.04) / 100
}

TEST(StudyMetrics, PixelVarianceAcrossRepeats) {
    const Image a = constantImage(3, 3, 1.0), b = constantImage(3, 3, 2.0), c = constantImage(3, 3, 3.0);
    EXPECT_NEAR(pixelVarianceAcrossRepeats({&a, &b, &c}), 1.0, 1e-12);
    EXPECT_EQ(pixelVarianceAcrossRepeats({&a}), 0.0);
}

TEST(StudyMetrics, BiasIsSignificantOnlyBeyondItsError) {
    const MeanWithError ref{1.0, 0.001};
    // Known errors (spp >= 2): 10% off with a 0.5% error is significant, 1% is not.
    EXPECT_TRUE(relativeBias({{1.10, 0.005}, {1.10, 0.005}}, ref).significant);
    EXPECT_FALSE(relativeBias({{1.01, 0.005}, {1.01, 0.005}}, ref).significant);
    // The spread of the repeats is used when larger than their stated errors.
    EXPECT_FALSE(relativeBias({{1.3, 0.001}, {0.9, 0.001}}, ref).significant);
    // Unknown errors (1 spp): the spread of 2 repeats is one degree of freedom, so even a z of ~20
    // (with spread ~0.005) is not significant; with 11 repeats it is.
    const BiasEstimate two = relativeBias({{1.095, 0}, {1.105, 0}}, ref);
    EXPECT_FALSE(two.significant) << two.z;
    EXPECT_GT(two.threshold, 1000);
    std::vector<MeanWithError> eleven;
    for (int i = 0; i < 11; ++i) eleven.push_back({1.1 + 0.001 * (i - 5), 0});
    EXPECT_TRUE(relativeBias(eleven, ref).significant);
    EXPECT_FALSE(relativeBias({{1.5, 0}}, ref).significant) << "one repeat at 1 spp cannot be judged";
    EXPECT_NEAR(studentCritical(2), 125.65, 1e-9);
    EXPECT_NEAR(studentCritical(1000), 4.0, 0.03);
}

TEST(StudyMetrics, RelativeErrorMap) {
    const Image ref = constantImage(2, 1, 0.99);
    const Image img = constantImage(2, 1, 1.99);
    for (float v : relativeErrorMap(img, ref)) EXPECT_NEAR(v, 1.0, 1e-6);
}

// ----------------------------------------------------------------------------------------------------
// The study on a tiny scene

class TinyStudy : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        dir_ = new fs::path(freshDir("tiny"));
        outcome_ = new StudyOutcome(runStudy(tinyConfig(*dir_)));
    }
    static void TearDownTestSuite() {
        fs::remove_all(*dir_);
        delete outcome_;
        delete dir_;
    }
    static fs::path* dir_;
    static StudyOutcome* outcome_;
};
fs::path* TinyStudy::dir_ = nullptr;
StudyOutcome* TinyStudy::outcome_ = nullptr;

TEST_F(TinyStudy, FlagsThePaperAsBiasedAndNotCosine) {
    ASSERT_FALSE(outcome_->cancelled);
    for (const StudySummary& s : outcome_->summary) {
        if (s.estimator == "paper") {
            EXPECT_TRUE(s.biasSignificant) << s.spp << " spp: z = " << s.biasZ;
        } else {
            EXPECT_FALSE(s.biasSignificant) << s.estimator << " " << s.spp << " spp: z = " << s.biasZ;
        }
    }
    EXPECT_NE(outcome_->conclusion.find("`paper`"), std::string::npos) << outcome_->conclusion;
}

TEST_F(TinyStudy, CsvHasAStableSchemaAndOneRowPerRender) {
    const std::string csv = readAll(*dir_ / "results.csv");
    EXPECT_EQ(csv.substr(0, csv.find('\n')),
              "scene,estimator,variant,sampler,mode,spp,repeat,width,height,seconds,rays,samples,mean_luminance,mean_luminance_std_error,"
              "relative_bias,mse_raw,mse,rmse,relmse,efficiency,efficiency_relmse,pixel_variance_within,group_relative_bias,"
              "group_bias_std_error,group_bias_z,group_bias_threshold,group_bias_significant,group_pixel_variance,split,"
              "group_first_bounce_variance,cpu_seconds,cost,paths,orbit");
    EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 1 + 3 * 2 * 2);
    EXPECT_EQ(outcome_->rows.size(), 12u);
    for (const StudyRow& r : outcome_->rows) {
        EXPECT_GT(r.seconds, 0);
        EXPECT_GT(r.cpuSeconds, 0);
        EXPECT_EQ(r.cost, r.cpuSeconds) << "the default cost is CPU time";
        EXPECT_DOUBLE_EQ(r.efficiency, 1.0 / (r.mse * r.cost));
        EXPECT_GT(r.rays, 0u);
        EXPECT_EQ(r.samples, 16u * 16u * r.spp);
        EXPECT_GT(r.rmse, 0);
    }
    // The MSE is a real error measure: for the unbiased `cosine` it falls about as 1/spp (4x from 16 to
    // 64 spp; between 2x and 8x allows for the noise of 2 repeats of a 16x16 image).
    double mse16 = 0, mse64 = 0;
    for (const StudyRow& r : outcome_->rows)
        if (r.estimator == "cosine") (r.spp == 16 ? mse16 : mse64) += r.mse;
    ASSERT_GT(mse64, 0);
    EXPECT_GT(mse16 / mse64, 2.0);
    EXPECT_LT(mse16 / mse64, 8.0);
}

// --splits adds "+splitK" variants of the --split-estimators only, and never splits a branch-mode set
// (it already traces many directions from its first hit).
TEST(StudyVariants, SplitsAddVariantsOfTheSplitEstimatorsOnly) {
    StudyConfig c;
    c.estimators = {"cosine", "phong", "symmetric-mix"};
    c.modes = {SymmetricMode::Branch, SymmetricMode::Spread};
    c.splits = {2, 4};
    std::vector<std::string> labels;
    for (const StudyVariant& v : studyVariants(c)) {
        labels.push_back(v.label);
        EXPECT_EQ(v.split, v.label.find("+split") == std::string::npos ? 1 : std::stoi(v.label.substr(v.label.find("+split") + 6)))
            << v.label;
    }
    const std::vector<std::string> expected = {"cosine",
                                               "phong",
                                               "phong+split2",
                                               "phong+split4",
                                               "symmetric-mix",
                                               "symmetric-mix+spread",
                                               "symmetric-mix+spread+split2",
                                               "symmetric-mix+spread+split4"};
    EXPECT_EQ(labels, expected);
}

// The progress bar's pilot renders each variant with the settings of its repeats (its first-hit split and
// its splitting; EARS long enough for its probe and first epochs) and the reference with its own. Checked
// by what the pilots trace, not their times: on the smooth-sky scene, where EARS splits nearly every first
// hit (docs/performance.md: 3.3 times phong's rays at 64 spp), the EARS pilot's rays per camera sample are
// far above phong's, as are +split8's (eight continuations a first hit); the EARS pilot at 2 samples a
// pixel (no probe, first-hit factors never learned: the pilot before) traces noticeably fewer. (At 64 spp and
// 128 x 96 EARS traces 3.3 times phong's rays here; the pilot's 2 times is nearer than 1.4.)
TEST(StudyPilot, RendersEachVariantAsItsRepeatsDo) {
    StudyConfig c;
    c.scene = SYMPHONG_SOURCE_DIR "/scenes/regime/sky-n10.json";
    c.estimators = {"phong"};
    c.splits = {8};
    c.splitEstimators = {"phong"};
    c.splittings = {"none", "ears"};
    c.width = 40, c.height = 30, c.threads = 2, c.maxDepth = 9;
    c.spps = {16};
    c.referenceSplitting = "ears";
    const Scene scene = loadScene(c.scene);
    const Accel accel(scene);
    std::map<std::string, double> raysPerSample;
    const auto pilotRays = [&](const StudyVariant& v) {
        const RenderSettings rs = pilotRenderSettings(c, v);
        const RenderResult r = render(scene, accel, *makeEstimator(v.estimator, variantOptions(c, v)), rs);
        return static_cast<double>(r.stats.rays) / static_cast<double>(r.stats.samples);
    };
    for (const StudyVariant& v : studyVariants(c)) {
        const RenderSettings rs = variantRenderSettings(c, v, 16);
        EXPECT_EQ(rs.width, 40);
        EXPECT_EQ(rs.height, 30);
        EXPECT_EQ(rs.threads, 2);
        EXPECT_EQ(rs.trace.maxDepth, 9);
        EXPECT_EQ(rs.spp, 16u);
        EXPECT_EQ(rs.sampler, v.sampler);
        EXPECT_EQ(rs.trace.firstHitSplit, v.split) << v.label;
        EXPECT_EQ(rs.trace.splitting, v.splitting) << v.label;
        EXPECT_EQ(pilotSpp(v.splitting), v.splitting == SplittingMode::None ? 2u : 2 * ears::kProbeMinSpp) << v.label;
        // The pilot: the variant's settings on a square of about its samples (at most one render of the
        // study's smallest: 40 x 30 x 4 here), at least kPilotMinSide a side.
        for (const std::vector<std::uint32_t>& spps : {std::vector<std::uint32_t>{4, 16}, std::vector<std::uint32_t>{64}}) {
            StudyConfig sized = c;
            sized.spps = spps;
            const RenderSettings pilot = pilotRenderSettings(sized, v);
            const std::uint64_t want = std::min<std::uint64_t>(kPilotSamples, 40 * 30 * spps.front());
            const auto samplesAt = [&](int side) {
                return static_cast<std::uint64_t>(side) * static_cast<std::uint64_t>(side) * pilot.spp;
            };
            EXPECT_EQ(pilot.spp, pilotSpp(v.splitting));
            EXPECT_EQ(pilot.width, pilot.height);
            EXPECT_EQ(pilot.trace.splitting, v.splitting);
            EXPECT_EQ(pilot.trace.firstHitSplit, v.split);
            EXPECT_GE(pilot.width, kPilotMinSide);
            EXPECT_GE(samplesAt(pilot.width), want) << v.label;
            if (pilot.width > kPilotMinSide) {
                EXPECT_LT(samplesAt(pilot.width - 1), want) << v.label;
            }
        }
        raysPerSample[v.label] = pilotRays(v);
    }
    ASSERT_EQ(raysPerSample.size(), 3u);
    EXPECT_GT(raysPerSample["phong+ears"], 1.8 * raysPerSample["phong"]);
    EXPECT_GT(raysPerSample["phong+split8"], 2.5 * raysPerSample["phong"]);
    // The reference's pilot: its renders' settings (its sampler and splitting, never the joint pattern nor a
    // first-hit split, which its render does not take either) at EARS's pilot spp.
    StudyConfig joint = c;
    joint.jointFirstBounce = true;
    const RenderSettings refRenders = referenceRenderSettings(joint, 1024);
    StudyConfig jointPlainReference = joint;
    jointPlainReference.referenceSplitting = "none";  // a variant of these settings would take the joint pattern
    EXPECT_FALSE(referenceRenderSettings(jointPlainReference, 1024).trace.jointFirstBounce);
    EXPECT_FALSE(pilotRenderSettings(jointPlainReference, referenceRenderSettings(jointPlainReference, 1024)).trace.jointFirstBounce);
    EXPECT_EQ(refRenders.spp, 1024u);
    EXPECT_EQ(refRenders.sampler, c.referenceSampler);
    EXPECT_EQ(refRenders.trace.splitting, SplittingMode::Ears);
    EXPECT_EQ(refRenders.trace.firstHitSplit, 1);
    EXPECT_FALSE(refRenders.trace.jointFirstBounce);
    EXPECT_EQ(refRenders.width, 40);
    EXPECT_EQ(refRenders.trace.maxDepth, 9);
    const RenderSettings refPilot = pilotRenderSettings(joint, refRenders);
    EXPECT_FALSE(refPilot.trace.jointFirstBounce);
    EXPECT_EQ(refPilot.spp, 2 * ears::kProbeMinSpp);
    EXPECT_EQ(refPilot.sampler, c.referenceSampler);
    StudyVariant plain;
    plain.estimator = "phong";
    EXPECT_TRUE(pilotRenderSettings(joint, plain).trace.jointFirstBounce) << "a variant's pilot takes the study's joint pattern";
    const RenderResult refResult = render(scene, accel, *makeEstimator(c.referenceEstimator, c.options), refPilot);
    EXPECT_GT(static_cast<double>(refResult.stats.rays) / static_cast<double>(refResult.stats.samples), 1.3 * raysPerSample["phong"]);
    // The pilot before: EARS at 2 samples a pixel, no probe, no learned first-hit factor.
    const std::vector<StudyVariant> variants = studyVariants(c);
    const auto ears = std::find_if(variants.begin(), variants.end(), [](const StudyVariant& v) { return v.label == "phong+ears"; });
    ASSERT_NE(ears, variants.end());
    const StudyVariant& shortEars = *ears;
    RenderSettings old = pilotRenderSettings(c, shortEars);
    old.spp = 2;
    const RenderResult r = render(scene, accel, *makeEstimator("phong", variantOptions(c, shortEars)), old);
    EXPECT_LT(static_cast<double>(r.stats.rays) / static_cast<double>(r.stats.samples), 0.8 * raysPerSample["phong+ears"]);
}

// The variance budget in a study: the rows of each variant at the top spp carry the first bounce's part of
// the pixel variance (positive in the Cornell box), the other spp none; the report has the table. Its
// values are checked against closed forms in tests/test_render.cpp (VarianceBudgetMatchesClosedForms...).
TEST(StudyBudget, FirstBounceVarianceIsMeasuredAtTheTopSpp) {
    const fs::path dir = freshDir("budget");
    StudyConfig c;
    c.scene = "cornell";
    c.estimators = {"cosine", "uniform"};
    c.spps = {4, 8};
    c.repeats = 2;
    c.width = c.height = 8;
    c.referenceSpp = 64;
    c.budgetPairs = 1;
    c.outDir = dir.string();
    c.plots = false;
    const StudyOutcome o = runStudy(c);
    for (const StudySummary& s : o.summary) {
        if (s.spp == 8) {
            EXPECT_GE(s.firstBounceVariance, 0.0) << s.variant;
            EXPECT_GT(s.firstBounceVariance, 0.0) << s.variant << ": the box's first bounce is random";
        } else {
            EXPECT_LT(s.firstBounceVariance, 0.0) << s.variant << " at " << s.spp << " spp: not measured";
        }
    }
    const std::string report = readAll(dir / "details.md");
    EXPECT_NE(report.find("## Variance budget (1 pairs)"), std::string::npos);
    EXPECT_NE(report.find("--budget-pairs 1"), std::string::npos);
    fs::remove_all(dir);
}

TEST_F(TinyStudy, JsonHasConfigRowsSummaryAndConclusion) {
    const auto j = nlohmann::json::parse(readAll(*dir_ / "results.json"));
    for (const char* key : {"config", "rows", "summary", "conclusion"}) EXPECT_TRUE(j.contains(key)) << key;
    EXPECT_EQ(j["rows"].size(), 12u);
    EXPECT_EQ(j["summary"].size(), 6u);
    for (const char* key : {"estimator", "variant", "sampler", "mode", "spp", "repeat", "seconds", "rays", "rmse", "relmse", "mse",
                            "efficiency", "group_relative_bias", "group_bias_std_error", "group_bias_significant", "group_pixel_variance"})
        EXPECT_TRUE(j["rows"][0].contains(key)) << key;
    for (const char* key : {"estimator", "spp", "repeats", "seconds", "cpu_seconds", "cost", "rmse", "rmse_spread", "efficiency",
                            "relative_bias", "bias_significant"})
        EXPECT_TRUE(j["summary"][0].contains(key)) << key;
    for (const char* key : {"estimators", "samplers", "variants", "spp", "repeats", "reference", "heatmap", "cost", "target_interval"})
        EXPECT_TRUE(j["config"].contains(key)) << key;
    EXPECT_EQ(j["config"]["cost"], "cpu");
    EXPECT_EQ(j["stopped_by"], "fixed");
    ASSERT_EQ(j["comparisons"].size(), 2u) << "cosine and paper against phong";
    EXPECT_EQ(j["comparisons"][0]["variant"], "cosine");
    EXPECT_EQ(j["comparisons"][0]["against"], "phong");
    EXPECT_EQ(j["comparisons"][1]["biased"], true);
}

// --samplers and --symmetric-modes: one variant per estimator x sampler (x mode for the set estimators),
// `stratified` once (its own sampler), each with its rows, the sampler it really used, and a conclusion
// that compares the samplers.
TEST(StudyVariants, SamplersAndModesMakeVariants) {
    StudyConfig c;
    c.estimators = {"cosine", "stratified", "symmetric"};
    c.samplers = {"independent", "sobol"};
    c.modes = {SymmetricMode::Branch, SymmetricMode::Spread};
    std::vector<std::string> labels;
    for (const StudyVariant& v : studyVariants(c)) labels.push_back(v.label);
    EXPECT_EQ(labels, (std::vector<std::string>{"cosine@independent", "cosine@sobol", "stratified", "symmetric@independent",
                                                "symmetric@sobol", "symmetric+spread@independent", "symmetric+spread@sobol"}));
    const fs::path dir = fs::temp_directory_path() / ("symphong-study-variants-" + std::to_string(::getpid()));
    fs::remove_all(dir);
    c.outDir = dir.string();
    c.width = c.height = 12;
    c.spps = {4};
    c.repeats = 2;
    c.referenceSpp = 64;
    c.plots = false;
    const StudyOutcome o = runStudy(c);
    ASSERT_EQ(o.rows.size(), 7u * 2u);
    for (const StudyRow& r : o.rows) {
        const bool spread = r.variant.find("+spread") != std::string::npos;
        EXPECT_EQ(r.mode, spread ? "spread" : "branch") << r.variant;
        EXPECT_EQ(r.sampler, r.estimator == "stratified" ? "stratified" : r.variant.substr(r.variant.find('@') + 1)) << r.variant;
        // A branch-mode symmetric camera sample traces its whole set; spread mode one path.
        if (r.estimator == "symmetric" && !spread) {
            EXPECT_GT(r.rays, 4u * 12u * 12u * 8u) << r.variant;
        }
    }
    EXPECT_NE(o.conclusion.find("lower MSE than `cosine@independent`"), std::string::npos) << o.conclusion;
    fs::remove_all(dir);
}

TEST_F(TinyStudy, WritesTheReportHeatmapsAndRenders) {
    const std::string report = readAll(*dir_ / "details.md");
    EXPECT_NE(report.find("## Conclusion in words"), std::string::npos);
    EXPECT_NE(report.find("## Equal cost"), std::string::npos);
    EXPECT_NE(report.find("| paper | 64 |"), std::string::npos) << report;
    for (const char* f : {"reference.exr", "reference.json", "reference.png", "renders/cosine.png", "renders/paper.png", "heatmaps/cosine.f32",
                          "renders/cosine@16spp.exr", "renders/paper@64spp.exr", "report.html"})
        EXPECT_GT(fs::file_size(*dir_ / f), 0u) << f;
    EXPECT_EQ(fs::file_size(*dir_ / "heatmaps/paper.f32"), 16u * 16u * sizeof(float));
}

// report.md answers first: "## The answer" within the first lines, at most ten lines of it, then one
// table per measure with a row per variant and a column per spp.
TEST_F(TinyStudy, ReportMdStartsWithTheAnswerAndOneTablePerMeasure) {
    const std::string report = readAll(*dir_ / "report.md");
    const std::size_t answer = report.find("## The answer\n\n");
    ASSERT_NE(answer, std::string::npos) << report;
    EXPECT_LT(std::count(report.begin(), report.begin() + static_cast<long>(answer), '\n'), 12) << "the answer comes first";
    const std::size_t end = report.find("\n\n", answer + 15);
    const std::string lines = report.substr(answer + 15, end - answer - 15);
    const long count = std::count(lines.begin(), lines.end(), '\n') + 1;
    EXPECT_LE(count, 10) << lines;
    EXPECT_NE(lines.find("**Most efficient by MSE** at 64 spp: `"), std::string::npos) << lines;
    EXPECT_EQ(lines.find("**Most efficient by MSE** at 64 spp: `paper`"), std::string::npos) << "`paper` is biased: " << lines;
    EXPECT_NE(lines.find("`paper` "), std::string::npos) << "the bias line names it: " << lines;
    EXPECT_NE(lines.find("[a, b] their 95% interval (delta method)"), std::string::npos) << lines;
    EXPECT_NE(lines.find("1/(MSE x CPU time)"), std::string::npos) << "the report says which cost it used: " << lines;
    EXPECT_NE(lines.find("Repeats: 2 per variant"), std::string::npos) << lines;
    for (const char* title : {"## Efficiency by MSE, relative to `phong` (95% interval)", "## Efficiency by relMSE, relative to `phong`",
                              "## RMSE of luminance (95% interval)", "## Repeats and cost at 64 spp"})
        EXPECT_NE(report.find(title), std::string::npos) << title;
    EXPECT_NE(report.find("| variant | 16 spp | 64 spp |"), std::string::npos) << report;
    EXPECT_NE(report.find("| `phong` | 1x | 1x |"), std::string::npos) << report;
    EXPECT_NE(report.find("| `paper` (biased) |"), std::string::npos) << report;
    EXPECT_NE(report.find("[report.html](report.html)"), std::string::npos);
}

namespace {

std::vector<unsigned char> decodeBase64(const std::string& s) {
    std::vector<unsigned char> out;
    unsigned buffer = 0;
    int bits = 0;
    for (char ch : s) {
        int v = -1;
        if (ch >= 'A' && ch <= 'Z') v = ch - 'A';
        if (ch >= 'a' && ch <= 'z') v = ch - 'a' + 26;
        if (ch >= '0' && ch <= '9') v = ch - '0' + 52;
        if (ch == '+') v = 62;
        if (ch == '/') v = 63;
        if (v < 0) continue;  // padding
        buffer = (buffer << 6) | static_cast<unsigned>(v);
        bits += 6;
        if (bits >= 8) {
            bits -= 8;
            out.push_back(static_cast<unsigned char>((buffer >> bits) & 0xff));
        }
    }
    return out;
}

/// binary16 to float by its definition: (-1)^s 2^(e - 15) (1 + m / 1024), subnormals 2^-14 m / 1024.
double halfValue(unsigned h) {
    const int e = (h >> 10) & 31, m = h & 1023;
    const double s = (h & 0x8000) ? -1 : 1;
    return e == 0 ? s * std::ldexp(m / 1024.0, -14) : s * std::ldexp(1 + m / 1024.0, e - 15);
}

nlohmann::json pageData(const std::string& html) {
    const std::string open = "<script id=\"study-data\" type=\"application/json\">";
    const std::size_t a = html.find(open);
    if (a == std::string::npos) return nullptr;
    const std::size_t b = html.find("</script>", a);
    return nlohmann::json::parse(html.substr(a + open.size(), b - a - open.size()));
}

}  // namespace

// report.html holds every variant's first repeat at every spp, bit for bit the half-float EXR beside it,
// the reference to half precision, FLIP maps of the right size, and the errors of each render computed
// again here.
TEST_F(TinyStudy, ReportHtmlCarriesEveryRenderAndItsErrors) {
    const nlohmann::json d = pageData(readAll(*dir_ / "report.html"));
    ASSERT_FALSE(d.is_null());
    EXPECT_EQ(d["width"], 16);
    EXPECT_EQ(d["spp"], (std::vector<int>{16, 64}));
    ASSERT_EQ(d["variants"].size(), 3u);
    const Image ref = readExr((*dir_ / "reference.exr").string());
    const auto refBytes = decodeBase64(d["reference"]["image"].get<std::string>());
    ASSERT_EQ(refBytes.size(), 16u * 16u * 6u);
    for (std::size_t i = 0; i < ref.pixels.size() * 3; ++i) {
        const double v = halfValue(refBytes[2 * i] | (refBytes[2 * i + 1] << 8)), want = ref.pixels[i / 3][static_cast<int>(i % 3)];
        ASSERT_NEAR(v, want, std::abs(want) / 2048 + 1e-7) << i;  // half: 11 significant bits
    }
    for (const auto& v : d["variants"]) {
        const std::string label = v["label"];
        ASSERT_EQ(v["images"].size(), 2u);
        for (const auto& e : v["images"]) {
            ASSERT_FALSE(e.is_null()) << label;
            const Image exr = readExr((*dir_ / "renders" / (label + "@" + std::to_string(e["spp"].get<int>()) + "spp.exr")).string());
            const auto bytes = decodeBase64(e["image"].get<std::string>());
            ASSERT_EQ(bytes.size(), 16u * 16u * 6u);
            for (std::size_t i = 0; i < exr.pixels.size() * 3; ++i)
                ASSERT_EQ(halfValue(bytes[2 * i] | (bytes[2 * i + 1] << 8)), exr.pixels[i / 3][static_cast<int>(i % 3)]) << label << " " << i;
            EXPECT_EQ(decodeBase64(e["flip"].get<std::string>()).size(), 16u * 16u);
            EXPECT_GT(e["flip_mean"].get<double>(), 0.0);
            EXPECT_LE(e["flip_mean"].get<double>(), 1.0);
            EXPECT_NEAR(e["rmse"].get<double>(), imageError(exr, ref).rmse, 1e-12) << label;
        }
    }
    EXPECT_EQ(d["tables"].size(), 4u);
    EXPECT_LE(d["answer"].size(), 10u);
}

TEST_F(TinyStudy, TheReferenceIsCachedAndReusedOnlyWhenTheSettingsMatch) {
    ASSERT_TRUE(outcome_->referenceRendered) << "the suite's first study renders its reference";
    // In a copy of the suite's directory: the studies below write their results over it, which the suite's
    // later tests read (run one by one, as ctest does, each has a directory of its own; run together, they share it).
    const fs::path dir = freshDir("cache");
    fs::copy(*dir_, dir, fs::copy_options::recursive);
    const std::string exr = readAll(dir / "reference.exr");
    // The cached reference gives the same numbers, bit for bit, as the freshly rendered one did.
    const StudyOutcome again = runStudy(tinyConfig(dir));
    EXPECT_FALSE(again.referenceRendered);
    ASSERT_EQ(again.rows.size(), outcome_->rows.size());
    for (std::size_t i = 0; i < again.rows.size(); ++i) {
        EXPECT_EQ(again.rows[i].mseRaw, outcome_->rows[i].mseRaw) << i;
        EXPECT_EQ(again.rows[i].mse, outcome_->rows[i].mse) << i;
        EXPECT_EQ(again.rows[i].relativeBias, outcome_->rows[i].relativeBias) << i;
        EXPECT_EQ(again.rows[i].groupBiasZ, outcome_->rows[i].groupBiasZ) << i;
    }
    StudyConfig c = tinyConfig(dir);
    c.estimators = {"cosine"};
    c.spps = {4};
    EXPECT_FALSE(runStudy(c).referenceRendered) << "same settings: the cached reference is reused";
    EXPECT_EQ(readAll(dir / "reference.exr"), exr);
    c.referenceSpp = 256;
    EXPECT_TRUE(runStudy(c).referenceRendered) << "other settings: a new reference";
    EXPECT_NE(readAll(dir / "reference.exr"), exr);
    EXPECT_EQ(nlohmann::json::parse(readAll(dir / "reference.json"))["key"]["spp"], 256);
    c.referenceSpp = 512;
    c.referenceSplitting = "ears";
    EXPECT_TRUE(runStudy(c).referenceRendered) << "a reference that splits is another reference";
    const nlohmann::json split = nlohmann::json::parse(readAll(dir / "reference.json"));
    EXPECT_EQ(split["key"]["splitting"], "ears");
    EXPECT_NE(readAll(dir / "reference.exr"), exr);
    const nlohmann::json results = nlohmann::json::parse(readAll(dir / "results.json"));
    EXPECT_EQ(results["config"]["reference"]["splitting"], "ears");
    EXPECT_NE(readAll(dir / "report.md").find("Reference: `phong+ears` at 512 spp"), std::string::npos);
    c.referenceSplitting = "none";
    EXPECT_TRUE(runStudy(c).referenceRendered);
    EXPECT_EQ(readAll(dir / "reference.exr"), exr) << "the same settings render the same reference, bit for bit";
    fs::remove_all(dir);
}

// A given --reference is used as it is: nothing rendered for it, the report says it was given, and the
// errors are measured against it (a reference twice as bright makes every row's bias about -50%).
TEST_F(TinyStudy, AGivenReferenceIsUsedInsteadOfRendering) {
    Image doubled = readExr((*dir_ / "reference.exr").string());
    for (Color& c : doubled.pixels) c *= 2.0;
    const fs::path dir = freshDir("given");
    fs::create_directories(dir);
    const std::string refPath = (dir / "given.exr").string();
    writeExr(doubled, refPath);
    StudyConfig c = tinyConfig(dir);
    c.estimators = {"cosine"};
    c.spps = {16};
    c.referencePath = refPath;
    const StudyOutcome o = runStudy(c);
    EXPECT_FALSE(o.referenceRendered);
    EXPECT_NE(readAll(dir / "report.md").find("given"), std::string::npos);
    ASSERT_FALSE(o.rows.empty());
    for (const StudyRow& r : o.rows) EXPECT_NEAR(r.relativeBias, -0.5, 0.05);
    fs::remove_all(dir);
}

TEST(Study, MakesEveryPlotAsPngAndSvg) {
    const fs::path dir = freshDir("plots");
    StudyConfig c = tinyConfig(dir);
    c.plots = true;
    c.referenceSpp = 256;
    const StudyOutcome o = runStudy(c);
    if (!o.plotted) {
        if (std::getenv("SYMPHONG_REQUIRE_PLOTS")) FAIL() << "the plots were not made";
        GTEST_SKIP() << "no python3 with matplotlib here";
    }
    for (const char* stem : {"convergence_spp", "convergence_time", "efficiency", "heatmaps", "crops"})
        for (const char* ext : {".png", ".svg"}) EXPECT_GT(fs::file_size(dir / (std::string(stem) + ext)), 1000u) << stem << ext;
    EXPECT_NE(readAll(dir / "details.md").find("![RMSE against samples per pixel](convergence_spp.png)"), std::string::npos);
    // report.html carries every plot inside it.
    const std::string html = readAll(dir / "report.html");
    EXPECT_NE(html.find("RMSE against render time"), std::string::npos);
    EXPECT_EQ(html.find("convergence_spp.png"), std::string::npos) << "plots are embedded, not linked";
    fs::remove_all(dir);
}

// Cancelling after a known row (deterministic: the row observer sets the flag) keeps exactly the
// finished groups.
TEST(Study, CancellingKeepsTheFinishedRows) {
    const fs::path dir = freshDir("cancel");
    StudyConfig c = tinyConfig(dir);
    c.estimators = {"cosine", "phong"};
    c.spps = {1, 2, 4, 8};
    c.referenceSpp = 16;
    std::atomic<bool> cancel{false};
    setStudyRowObserver([&](std::size_t rows) {
        if (rows == 3) cancel = true;  // in the middle of the second group (2 repeats per group)
    });
    const StudyOutcome o = runStudy(c, &cancel);
    setStudyRowObserver(nullptr);
    EXPECT_TRUE(o.cancelled);
    EXPECT_EQ(o.rows.size(), 2u) << "the unfinished second group is dropped, the first kept";
    const std::string csv = readAll(dir / "results.csv");
    EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 1 + 2);
    EXPECT_NE(readAll(dir / "report.md").find("Interrupted"), std::string::npos);
    EXPECT_FALSE(fs::exists(dir / "report.html")) << "written only when the study finishes";
    fs::remove_all(dir);
}

// --resume: a study cancelled in its second group keeps the first; run again with --resume it keeps that
// group (not rendered again) and renders the rest, and every row equals an uninterrupted study's, the
// times aside. Resuming with another seed is refused, naming it.
TEST(Study, ResumeKeepsTheFinishedGroupsAndEndsWithAnUninterruptedStudysRows) {
    const fs::path whole = freshDir("resume-whole"), parts = freshDir("resume-parts");
    StudyConfig c = tinyConfig(whole);
    c.estimators = {"cosine", "phong"};
    c.spps = {1, 2, 4};
    c.referenceSpp = 32;
    const StudyOutcome expected = runStudy(c);
    c.outDir = parts.string();
    std::atomic<bool> cancel{false};
    setStudyRowObserver([&](std::size_t rows) {
        if (rows == 3) cancel = true;
    });
    ASSERT_TRUE(runStudy(c, &cancel).cancelled);
    setStudyRowObserver(nullptr);
    c.resume = true;
    std::size_t rendered = 0;
    setStudyRowObserver([&](std::size_t) { ++rendered; });
    const StudyOutcome resumed = runStudy(c);
    setStudyRowObserver(nullptr);
    EXPECT_FALSE(resumed.cancelled);
    EXPECT_EQ(resumed.keptRows, 2);
    EXPECT_EQ(rendered, expected.rows.size() - 2) << "the kept group is not rendered again";
    ASSERT_EQ(resumed.rows.size(), expected.rows.size());
    for (std::size_t i = 0; i < expected.rows.size(); ++i) {
        const StudyRow &a = expected.rows[i], &b = resumed.rows[i];
        EXPECT_EQ(a.variant, b.variant) << i;
        EXPECT_EQ(a.spp, b.spp) << i;
        EXPECT_EQ(a.repeat, b.repeat) << i;
        EXPECT_EQ(a.meanLuminance, b.meanLuminance) << i;
        EXPECT_EQ(a.mse, b.mse) << i;
        EXPECT_EQ(a.relMse, b.relMse) << i;
        EXPECT_EQ(a.groupRelativeBias, b.groupRelativeBias) << i;
        EXPECT_EQ(a.groupPixelVariance, b.groupPixelVariance) << i;
    }
    c.seed = 2;
    try {
        runStudy(c);
        ADD_FAILURE() << "a resume with another seed was accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("the earlier study had seed 1, not 2"), std::string::npos) << e.what();
    }
    // A study written before a setting existed (here --reference-splitting: its results lack the key) resumes
    // under that setting's default, and only under it.
    c.seed = 1;
    nlohmann::json saved = nlohmann::json::parse(readAll(parts / "results.json"));
    ASSERT_EQ(saved["settings"].erase("reference_splitting"), 1u);
    writeFile((parts / "results.json").string(), saved.dump(2));
    rendered = 0;
    setStudyRowObserver([&](std::size_t) { ++rendered; });
    EXPECT_EQ(runStudy(c).keptRows, static_cast<int>(expected.rows.size()));
    setStudyRowObserver(nullptr);
    EXPECT_EQ(rendered, 0u);
    saved = nlohmann::json::parse(readAll(parts / "results.json"));
    ASSERT_EQ(saved["settings"].erase("reference_splitting"), 1u);
    writeFile((parts / "results.json").string(), saved.dump(2));
    c.referenceSplitting = "ears";
    try {
        runStudy(c);
        ADD_FAILURE() << "a resume with a reference that splits was accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("the earlier study had reference_splitting (not set), not \"ears\""), std::string::npos)
            << e.what();
    }
    fs::remove_all(whole);
    fs::remove_all(parts);
}

TEST(Study, BadConfigurationsAreInputErrors) {
    const fs::path dir = freshDir("bad");
    StudyConfig c = tinyConfig(dir);
    c.estimators = {"cosin"};
    EXPECT_THROW(runStudy(c), InputError);
    c = tinyConfig(dir);
    c.spps = {0, 4};
    EXPECT_THROW(runStudy(c), InputError);
    c = tinyConfig(dir);
    c.referenceEstimator = "paper";
    EXPECT_THROW(runStudy(c), InputError);
    c = tinyConfig(dir);
    c.referenceSplitting = "ears-orbit";
    c.referenceEstimator = "cosine";  // ears-orbit's orbits are phong's
    EXPECT_THROW(runStudy(c), InputError);
    c = tinyConfig(dir);
    c.referencePath = (dir / "missing.exr").string();
    EXPECT_THROW(runStudy(c), InputError);
    c = tinyConfig(dir);
    c.heatmapSpp = 5;
    EXPECT_THROW(runStudy(c), InputError);
    // A given reference of the wrong size.
    fs::create_directories(dir);
    writeExr(constantImage(8, 8, 1.0), (dir / "ref8.exr").string());
    c = tinyConfig(dir);
    c.referencePath = (dir / "ref8.exr").string();
    try {
        runStudy(c);
        FAIL();
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("8x8 does not match"), std::string::npos) << e.what();
    }
    fs::remove_all(dir);
}

TEST(Study, CommandLineRejectsBadInput) {
    const auto run = [](std::vector<std::string> args) {
        const test::CliRun r = test::runCliArgs(std::move(args));
        return std::make_pair(r.code, r.err);
    };
    const std::string out = freshDir("cli").string();
    auto [code, err] = run({"study", "--estimators", "cosine,bogus", "-o", out});
    EXPECT_EQ(code, 2);
    EXPECT_NE(err.find("bogus"), std::string::npos);
    std::tie(code, err) = run({"study", "--spp", "0", "-o", out});
    EXPECT_EQ(code, 2);
    std::tie(code, err) = run({"study", "--repeats", "0", "-o", out});
    EXPECT_EQ(code, 2);
    std::tie(code, err) = run({"study", "--reference", out + "/none.exr", "-o", out});
    EXPECT_EQ(code, 2);
    EXPECT_NE(err.find("none.exr"), std::string::npos);
    fs::remove_all(out);
}

// Ctrl-C through the command line: SIGINT (raised after the fourth row, deterministically) stops the
// study, exit code 130, the two finished groups kept.
TEST(Study, InterruptFromTheCommandLineKeepsTheFinishedRows) {
    const fs::path dir = freshDir("sigint");
    setStudyRowObserver([](std::size_t rows) {
        if (rows == 4) std::raise(SIGINT);
    });
    const test::CliRun r = test::runCliArgs({"study", "-e", "cosine,phong", "--spp", "1,2,4,8", "-R", "2", "-W", "16", "-H", "16",
                                             "--reference-spp", "16", "--no-plots", "-o", dir.string()});
    setStudyRowObserver(nullptr);
    EXPECT_EQ(r.code, 130) << r.err;
    EXPECT_NE(r.err.find("interrupted; 4 finished row(s) kept"), std::string::npos) << r.err;
    const std::string csv = readAll(dir / "results.csv");
    EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 1 + 4);
    fs::remove_all(dir);
}

TEST(StudyMetrics, LuminanceVarianceTakesTheChannelsAsCorrelated) {
    EXPECT_NEAR(luminanceVariance(Color(0.04)), 0.04, 1e-15);  // grey: Var(Y) = Var(X) when X = R = G = B
    EXPECT_NEAR(luminanceVariance(Color(0, 0.01, 0)), 0.7152 * 0.7152 * 0.01, 1e-15);
}

// ----------------------------------------------------------------------------------------------------
// Cost, repeats until the answer is sure, fair pairs

// The CPU clock of the process counts every thread's work and not its waiting: two threads that each
// burn 0.15 s of their own CPU clock (a second method: CLOCK_THREAD_CPUTIME_ID) add 0.3 s; a sleep adds none.
TEST(StudyCost, CpuTimeCountsEveryThreadsWorkAndNotItsWaiting) {
    const auto threadCpu = [] {
        timespec t{};
        clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
        return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
    };
    const auto burn = [&] {
        const double start = threadCpu();
        volatile double x = 0;
        while (threadCpu() - start < 0.15) x = x + 1;
    };
    double before = processCpuSeconds();
    std::thread a(burn), b(burn);
    a.join();
    b.join();
    const double busy = processCpuSeconds() - before;
    EXPECT_GE(busy, 0.30);
    EXPECT_LT(busy, 0.36) << "only the two threads ran";
    before = processCpuSeconds();
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    EXPECT_LT(processCpuSeconds() - before, 0.02);
}

namespace {

/// A floor far larger than the view, looked at from above, lit by a point light: with max depth 1 and
/// `cosine`, a camera sample traces its camera ray, one shadow ray and one ray per direction from the floor.
std::string floorScene(const test::TempDir& dir) {
    dir.write("floor.obj", "v -100 0 -100\nv 100 0 -100\nv 100 0 100\nv -100 0 100\nf 1 3 2\nf 1 4 3\n");
    return dir.write("floor.json", R"({"obj": "floor.obj", "camera": {"position": [0, 1, 0], "target": [0, 0, 0], "up": [0, 0, -1], "fov": 40},
      "environment": 0, "lights": [{"type": "point", "position": [0, 2, 0], "intensity": 1}]})");
}

}  // namespace

TEST(StudyCost, RaysAndPathsEqualACountMadeByHand) {
    const test::TempDir dir;
    const Scene scene = loadScene(floorScene(dir));
    const Accel accel(scene);
    const auto est = makeEstimator("cosine");
    RenderSettings s;
    s.width = s.height = 8;
    s.spp = 4;
    s.trace.maxDepth = 1;
    const std::uint64_t samples = 8 * 8 * 4;
    for (int split : {1, 3}) {
        s.trace.firstHitSplit = split;
        const RenderResult r = render(scene, accel, *est, s);
        EXPECT_EQ(r.stats.samples, samples);
        EXPECT_EQ(r.stats.rays, samples * (2 + split)) << "camera + shadow + " << split << " from the floor";
        EXPECT_EQ(r.stats.paths, samples * split);
        EXPECT_GT(r.stats.cpuSeconds, 0.0);
    }
    // The study's rays cost is that count.
    StudyConfig c;
    c.scene = floorScene(dir);
    c.estimators = {"cosine", "phong"};
    c.spps = {4};
    c.repeats = 2;
    c.width = c.height = 8;
    c.maxDepth = 1;
    c.referenceSpp = 16;
    c.cost = StudyCost::Rays;
    c.outDir = dir.file("study");
    c.plots = false;
    for (const StudyRow& r : runStudy(c).rows) {
        EXPECT_EQ(r.cost, static_cast<double>(samples * 3)) << r.variant;
        EXPECT_DOUBLE_EQ(r.efficiency, 1.0 / (r.mse * r.cost));
    }
    EXPECT_NE(readAll(fs::path(c.outDir) / "report.md").find("1/(MSE x rays traced)"), std::string::npos);
}

namespace {

/// The rows of results.csv as maps from column name to text.
std::vector<std::map<std::string, std::string>> csvRows(const fs::path& file) {
    std::istringstream in(readAll(file));
    std::string line;
    std::getline(in, line);
    std::vector<std::string> names;
    for (std::string::size_type a = 0, b; a <= line.size(); a = b + 1) {
        b = std::min(line.find(',', a), line.size());
        names.push_back(line.substr(a, b - a));
    }
    std::vector<std::map<std::string, std::string>> rows;
    while (std::getline(in, line)) {
        std::map<std::string, std::string> row;
        std::size_t i = 0;
        for (std::string::size_type a = 0, b; a <= line.size() && i < names.size(); a = b + 1, ++i) {
            b = std::min(line.find(',', a), line.size());
            row[names[i]] = line.substr(a, b - a);
        }
        rows.push_back(row);
    }
    return rows;
}

}  // namespace

// Fair pairs: `symmetric-mix` with an orbit of 2 against `phong` split 2 ways, and its spread mode against
// plain `phong`, each a line of the answer with its verdict; the factor in the line and in results.json is
// computed again here from results.csv (mean MSE x mean cost, repeats paired by number).
TEST(StudyFairPairs, PairLinesCompareEqualPathsAndMatchTheCsv) {
    const fs::path dir = freshDir("pairs");
    StudyConfig c = tinyConfig(dir);
    c.estimators = {"phong", "symmetric-mix"};
    c.modes = {SymmetricMode::Branch, SymmetricMode::Spread};
    c.splits = {2};
    c.splitEstimators = {"phong"};
    c.orbits = {2};
    c.spps = {8};
    c.repeats = 3;
    c.referenceSpp = 128;
    const StudyOutcome o = runStudy(c);
    std::vector<std::string> labels;
    for (const StudyVariant& v : studyVariants(c)) labels.push_back(v.label);
    EXPECT_EQ(labels, (std::vector<std::string>{"phong", "phong+split2", "symmetric-mix+orbit2", "symmetric-mix+spread"}));
    std::string answer;
    for (const std::string& l : o.answer) answer += l + "\n";
    EXPECT_NE(answer.find("`symmetric-mix+orbit2` against `phong+split2` (2 paths per camera sample): **"), std::string::npos) << answer;
    EXPECT_NE(answer.find("`symmetric-mix+spread` against `phong` (one path per camera sample): **"), std::string::npos) << answer;
    EXPECT_NE(answer.find("of 2 fair pairs"), std::string::npos) << answer;
    // Paths: split 2 starts two per camera sample; the orbit two where the first hit branches.
    for (const StudyRow& r : o.rows) {
        const std::uint64_t k = r.variant == "phong+split2" || r.variant == "symmetric-mix+orbit2" ? 2 : 1;
        EXPECT_LE(r.paths, k * r.samples) << r.variant;
        EXPECT_GE(r.paths, k == 2 ? r.samples * 3 / 2 : r.samples) << r.variant;
        EXPECT_EQ(r.orbit, r.variant == "symmetric-mix+orbit2" ? 2 : r.estimator == "symmetric-mix" ? 2 : 0) << r.variant;
    }
    // The same factors from the CSV.
    const auto rows = csvRows(dir / "results.csv");
    const auto product = [&](const std::string& variant) {
        double mse = 0, cost = 0, n = 0;
        for (const auto& r : rows)
            if (r.at("variant") == variant) mse += std::stod(r.at("mse")), cost += std::stod(r.at("cost")), ++n;
        return (mse / n) * (cost / n);
    };
    const auto j = nlohmann::json::parse(readAll(dir / "results.json"));
    int pairs = 0;
    for (const auto& cmp : j["comparisons"]) {
        if (!cmp["fair_pair"].get<bool>()) continue;
        ++pairs;
        const std::string a = cmp["variant"], b = cmp["against"];
        const double expected = product(b) / product(a);
        EXPECT_NEAR(cmp["mse"]["ratio"].get<double>(), expected, 2e-5 * expected) << a;
        EXPECT_NE(answer.find(fmt::format("`{}` against `{}`", a, b)), std::string::npos);
        EXPECT_NE(answer.find(fmt::format("{:#.2g}x [", expected)), std::string::npos) << a << " " << expected << "\n" << answer;
        EXPECT_EQ(cmp["repeats_variant"], 3);
    }
    EXPECT_EQ(pairs, 2);
    fs::remove_all(dir);
}

// The answer's "Most efficient" lines, against results.csv: the variant each names first is the most efficient
// unbiased one by that line's measure (1/(mean error x mean cost) over the top spp's repeats), the one it
// calls the next is the second, and each factor it quotes, with its interval, is the ratio computed again
// from the CSV's columns (mse for the MSE line, relmse for the relMSE line; answer_factors.h). The study's two
// unbiased variants are within noise of each other (at this seed `cosine` first by MSE, 1.01x, and `phong`
// by relMSE, 1.09x), so which measure a line uses shows here by chance only: the rows made to differ in
// StudyAnswer.MostEfficientLinesQuoteTheRatiosOfTheirOwnMeasure tell the measures apart by a margin; this
// test checks the whole way from the renders through results.csv to the text.
TEST_F(TinyStudy, AnswerFactorsAreTheRatiosOfResultsCsv) {
    const auto rows = csvRows(*dir_ / "results.csv");
    std::uint32_t top = 0;
    std::set<std::string> biased, variants;
    for (const auto& r : rows) {
        top = std::max<std::uint32_t>(top, static_cast<std::uint32_t>(std::stoul(r.at("spp"))));
        if (r.at("group_bias_significant") == "1") biased.insert(r.at("variant"));
    }
    const auto samples = [&](const std::string& variant, const char* column) {
        std::vector<answer_factors::Sample> out;
        for (const auto& r : rows)
            if (r.at("variant") == variant && std::stoul(r.at("spp")) == top)
                out.push_back({std::stoi(r.at("repeat")), std::stod(r.at(column)), std::stod(r.at("cost"))});
        return out;
    };
    for (const auto& r : rows)
        if (!biased.count(r.at("variant"))) variants.insert(r.at("variant"));
    ASSERT_EQ(variants, (std::set<std::string>{"cosine", "phong"})) << "`paper` is biased";
    const double referenceNoiseSd = nlohmann::json::parse(readTextFile((*dir_ / "results.json").string())).at("config").at("reference").at("noise_sd");
    EXPECT_GT(referenceNoiseSd, 0);
    int lines = 0;
    for (const std::string& text : outcome_->answer) {
        const auto line = answer_factors::parseMostEfficient(text);
        if (!line) continue;
        ++lines;
        const char* column = text.find("by relMSE") != std::string::npos ? "relmse" : "mse";
        // The most efficient by the CSV: the other unbiased variant's ratio against it is at most 1.
        for (const std::string& v : variants) {
            if (v == line->best) continue;
            EXPECT_LE(answer_factors::ratio(samples(v, column), samples(line->best, column)).point, 1.0) << text;
        }
        ASSERT_EQ(line->factors.size(), 1u) << "two unbiased variants: only the next is quoted: " << text;
        EXPECT_NE(line->factors[0].against, line->best);
        EXPECT_TRUE(variants.count(line->factors[0].against)) << text;
        // By MSE the interval also carries the reference's own error (results.json: config, reference, noise_sd).
        const double shared = std::string(column) == "mse" ? referenceNoiseSd : 0.0;
        const answer_factors::Quoted computed =
            answer_factors::ratio(samples(line->best, column), samples(line->factors[0].against, column), shared);
        std::printf("%s: %s against %s, %.4f [%.4f, %.4f] from the CSV\n", column, line->best.c_str(), line->factors[0].against.c_str(),
                    computed.point, computed.lo, computed.hi);
        answer_factors::expectQuotes(line->factors[0], computed, text);
    }
    EXPECT_EQ(lines, 2) << "one line by MSE, one by relMSE";
}

// --target-interval with --time: rounds of repeats at the top spp only, until the budget; the report and
// results.json say what stopped it. With --max-repeats: no variant beyond it.
TEST(StudyRepeats, TimeAndMaxRepeatsStopTheRoundsAndTheReportSaysSo) {
    const fs::path dir = freshDir("rounds");
    StudyConfig c = tinyConfig(dir);
    c.estimators = {"cosine", "phong"};
    c.width = c.height = 12;
    c.spps = {2, 4};
    c.repeats = 2;
    c.referenceSpp = 64;
    // The time budget: half again what the study takes without rounds (so at least one round starts, at any
    // speed: a sanitizer's too); a target no test reaches.
    const double plain = runStudy(c).studySeconds;
    c.targetInterval = 0.001;
    c.timeLimit = 1.5 * plain + 0.2;
    StudyOutcome o = runStudy(c);
    EXPECT_EQ(o.stoppedBy, "time");
    EXPECT_LT(o.studySeconds, 3 * c.timeLimit) << "no round starts that would end well after the budget";
    for (const char* v : {"cosine", "phong"}) {
        EXPECT_EQ(repeatsOf(o.rows, v, 2), 2) << "the lower spp keeps --repeats";
        EXPECT_GT(repeatsOf(o.rows, v, 4), 2) << "rounds were added at the top spp";
    }
    std::string answer;
    for (const std::string& l : o.answer) answer += l + "\n";
    EXPECT_NE(answer.find("stopped by the --time budget"), std::string::npos) << answer;
    EXPECT_NE(readAll(dir / "report.md").find("stopped by the --time budget"), std::string::npos);
    EXPECT_EQ(nlohmann::json::parse(readAll(dir / "results.json"))["stopped_by"], "time");
    // Repeats are numbered 0, 1, 2, ... in every variant: paired by number (and seed) with the yardstick.
    for (const char* v : {"cosine", "phong"}) {
        std::vector<int> reps;
        for (const StudyRow& r : o.rows)
            if (r.variant == v && r.spp == 4) reps.push_back(r.repeat);
        for (std::size_t i = 0; i < reps.size(); ++i) EXPECT_EQ(reps[i], static_cast<int>(i)) << v;
    }
    fs::remove_all(dir);
    c.timeLimit = 0;
    c.maxRepeats = 4;
    o = runStudy(c);
    EXPECT_EQ(o.stoppedBy, "max-repeats");
    for (const char* v : {"cosine", "phong"}) EXPECT_EQ(repeatsOf(o.rows, v, 4), 4) << v;
    fs::remove_all(dir);
}

TEST(StudyRepeats, BadTargetsAreInputErrors) {
    const fs::path dir = freshDir("bad-target");
    StudyConfig c = tinyConfig(dir);
    c.targetInterval = -1;
    EXPECT_THROW(runStudy(c), InputError);
    c = tinyConfig(dir);
    c.targetInterval = 0.1;
    c.repeats = 1;
    EXPECT_THROW(runStudy(c), InputError);
    c = tinyConfig(dir);
    c.orbits = {3};
    EXPECT_THROW(runStudy(c), InputError);
    const auto [code, err] = [&] {
        const test::CliRun r = test::runCliArgs({"study", "--cost", "seconds", "-o", dir.string()});
        return std::pair{r.code, r.err};
    }();
    EXPECT_EQ(code, 2);
    EXPECT_NE(err.find("unknown cost 'seconds' (valid: cpu, wall, rays)"), std::string::npos) << err;
    fs::remove_all(dir);
}

TEST(Study, NoPageLeavesReportHtmlOutAndSaysSo) {
    const fs::path dir = freshDir("no-page");
    StudyConfig c = tinyConfig(dir);
    c.estimators = {"phong"};
    c.spps = {2};
    fs::create_directories(dir);
    writeFile((dir / "report.html").string(), "an earlier run's page");
    c.page = false;
    runStudy(c);
    EXPECT_FALSE(fs::exists(dir / "report.html")) << "an earlier page would not match these rows";
    const std::string md = readAll(dir / "report.md");
    EXPECT_NE(md.find("No report.html (`--no-page`)"), std::string::npos);
    EXPECT_NE(readAll(dir / "details.md").find("Plots were not asked for (`--no-plots`)"), std::string::npos);
    fs::remove_all(dir);
}
