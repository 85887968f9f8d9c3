// Furnace tests of every estimator at a single shading point: under a constant incoming radiance
// L = 1 the reflected radiance is the directional albedo, known exactly (materials/phong.h). Each
// estimator's mean must match it within 4 standard errors, for diffuse and glossy Phong materials
// and view angles up to 85 degrees. Also: the weights and MIS densities estimators report agree.
#include "estimators/estimator.h"
#include "sampling/warp.h"
#include "stats.h"

#include <gtest/gtest.h>

#include <fmt/format.h>

#include <algorithm>

using namespace symphong;

namespace {

struct FurnaceCase {
    double kd, ks, n, thetaDeg;
};

std::vector<FurnaceCase> furnaceCases() {
    std::vector<FurnaceCase> cases;
    for (double deg : {0.0, 30.0, 60.0, 85.0}) {
        cases.push_back({0.8, 0.0, 1.0, deg});
        for (double n : {1.0, 10.0, 100.0, 1000.0}) cases.push_back({0.2, 0.7, n, deg});
    }
    return cases;
}

class EstimatorFurnace : public ::testing::TestWithParam<std::string> {};

/// Every estimator but `paper`, which is biased on purpose.
std::vector<std::string> unbiasedEstimators() {
    std::vector<std::string> names;
    for (const auto& n : estimatorNames())
        if (n != "paper") names.push_back(n);
    return names;
}

}  // namespace

// One estimate = the mean of a group of 16 calls with sample indices 0..15 of 16 (so the stratified
// estimator sees whole pixels); groups are independent, so their spread gives the standard error.
// Half the groups let estimators return their whole direction set (first hit), half one direction
// (deeper bounces): both must be unbiased.
TEST_P(EstimatorFurnace, MatchesTheDirectionalAlbedo) {
    const auto estimator = makeEstimator(GetParam());
    Rng rng(1234, 5);
    std::vector<DirectionSample> out;
    constexpr std::uint32_t kGroup = 16;
    // Estimators that return a whole set of directions per call need fewer calls for the same precision.
    const int kGroups = estimator->returnsSets() ? 4000 : 20000;
    for (const FurnaceCase& c : furnaceCases()) {
        PhongMaterial m;
        m.rhoD = Color(c.kd);
        m.rhoS = Color(c.ks);
        m.exponent = c.n;
        const Vec3 wo = sphericalDirection(std::cos(c.thetaDeg * kPi / 180), 0.7);
        const double exact = phongDirectionalAlbedo(m, wo).x;
        for (bool branch : {true, false}) {
            std::vector<double> groups(kGroups / 2);
            for (double& g : groups) {
                double sum = 0;
                for (std::uint32_t i = 0; i < kGroup; ++i) {
                    out.clear();
                    estimator->sample(ShadingContext{wo, &m, 0, i, kGroup, branch}, rng, out);
                    for (const auto& s : out) sum += s.weight.x;
                }
                g = sum / kGroup;
            }
            const auto s = test::meanAndError(groups);
            const std::string what = fmt::format("{} (branch {}): kd {} ks {} n {} theta {} -> {} +- {} vs exact {}", GetParam(),
                                                 branch, c.kd, c.ks, c.n, c.thetaDeg, s.mean, s.stdError, exact);
            EXPECT_NEAR(s.mean, exact, 4 * s.stdError + 1e-9 * exact) << what;
        }
    }
}

TEST_P(EstimatorFurnace, WeightsAreBrdfCosineOverTheReportedDensity) {
    const auto estimator = makeEstimator(GetParam());
    Rng rng(77, 7);
    PhongMaterial m;
    m.rhoD = Color(0.3);
    m.rhoS = Color(0.5);
    m.exponent = 20;
    std::vector<DirectionSample> out;
    for (bool branch : {false, true})
        for (int k = 0; k < 2000; ++k) {
            const Vec3 wo = sampleUniformHemisphere(rng.uniform2());
            const ShadingContext ctx{wo, &m, branch ? 0 : 1, 0, 1, branch};
            out.clear();
            estimator->sample(ctx, rng, out);
            if (!branch || !estimator->returnsSets()) {
                ASSERT_LE(out.size(), 1u) << "without a set an estimator returns at most one direction";
            }
            for (const auto& s : out) {
                ASSERT_GT(s.wi.z, 0);
                const Color f = evalPhong(m, wo, s.wi);
                EXPECT_NEAR(s.weight.x * s.misPdf, f.x * s.wi.z, 1e-9 * f.x * s.wi.z);
                EXPECT_NEAR(estimator->misPdf(ctx, s.wi), s.misPdf, 1e-12 * s.misPdf);
            }
        }
}

TEST(EstimatorRegistry, UnknownNameListsTheValidOnes) {
    try {
        makeEstimator("cosin");
        FAIL() << "no exception";
    } catch (const std::invalid_argument& e) {
        const std::string msg = e.what();
        EXPECT_NE(msg.find("cosin"), std::string::npos);
        for (const auto& n : estimatorNames()) EXPECT_NE(msg.find(n), std::string::npos) << msg;
    }
}

INSTANTIATE_TEST_SUITE_P(AllUnbiasedEstimators, EstimatorFurnace, ::testing::ValuesIn(unbiasedEstimators()),
                         [](const auto& info) {
                             std::string n = info.param;
                             std::replace(n.begin(), n.end(), '-', '_');
                             return n;
                         });

// At deeper bounces `paper` keeps one of its directions: the same expectation as the whole set.
TEST(PaperEstimator, OneDirectionHasTheSameMeanAsTheWholeSet) {
    const auto paper = makeEstimator("paper", EstimatorOptions{2, false});
    PhongMaterial m;
    m.rhoD = Color(0.5);
    m.rhoS = Color(0.4);
    m.exponent = 20;
    const Vec3 wo = sphericalDirection(std::cos(0.5), 0.3);
    Rng rng(31, 31);
    std::vector<DirectionSample> out;
    for (bool branch : {true, false}) {
        std::vector<double> v(branch ? 50000 : 2000000);
        for (double& x : v) {
            out.clear();
            paper->sample(ShadingContext{wo, &m, branch ? 0 : 1, 0, 1, branch}, rng, out);
            x = 0;
            for (const auto& s : out) x += s.weight.x;
        }
        const auto s = test::meanAndError(v);
        static double whole = 0, wholeSe = 0;
        if (branch) {
            whole = s.mean;
            wholeSe = s.stdError;
        } else {
            EXPECT_NEAR(s.mean, whole, 4 * std::sqrt(s.stdError * s.stdError + wholeSe * wholeSe));
        }
    }
}
