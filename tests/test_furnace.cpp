// The single-point furnace: exact values of every environment checked independently, `symmetric` and
// `symmetric-shifted` unbiased (error bars from 16 independent runs) on the whole furnace grid and on
// every environment, and the `paper` estimator's bias detected.
#include "estimators/symmetric.h"
#include "materials/phong.h"
#include "sampling/warp.h"
#include "stats.h"
#include "study/environment.h"
#include "study/furnace.h"
#include "compare/metrics.h"

#include <gtest/gtest.h>

#include <fmt/format.h>

#include <cmath>

using namespace symphong;

TEST(Environments, ConstantMatchesTheDirectionalAlbedo) {
    const Environment env = makeEnvironment("constant");
    for (double n : {1.0, 10.0, 100.0, 1000.0, 10000.0})
        for (double deg : {0.0, 30.0, 60.0, 85.0}) {
            PhongMaterial m;
            m.rhoD = Color(0.3);
            m.rhoS = Color(0.6);
            m.exponent = n;
            const Vec3 wo = sphericalDirection(std::cos(deg * kPi / 180), 0.4);
            EXPECT_NEAR(exactReflected(env, 0.3, 0.6, n, wo), phongDirectionalAlbedo(m, wo).x, 1e-9) << n << " " << deg;
        }
}

// Each exact value against an independent Monte Carlo estimate (Phong-lobe importance sampling with many
// samples), within 4 standard errors.
TEST(Environments, ExactValuesMatchMonteCarlo) {
    Rng rng(21, 21);
    for (const std::string& name : environmentNames())
        for (double n : {1.0, 50.0})
            for (double deg : {20.0, 70.0}) {
                const Environment env = makeEnvironment(name);
                PhongMaterial m;
                m.rhoD = Color(0.4);
                m.rhoS = Color(0.5);
                m.exponent = n;
                const Vec3 wo = sphericalDirection(std::cos(deg * kPi / 180), 0.0);
                const Vec3 r(-wo.x, -wo.y, wo.z);
                std::vector<double> v(400000);
                for (double& x : v) {
                    // Mixture: half cosine, half lobe; weight f cos L / pdf.
                    const bool lobe = rng.uniform() < 0.5;
                    Vec3 wi = sampleCosineHemisphere(rng.uniform2());
                    if (lobe) {
                        const Vec3 l = samplePhongLobe(rng.uniform2(), n);
                        const Vec3 ax = r, t = normalize(cross(std::abs(ax.x) > 0.5 ? Vec3(0, 1, 0) : Vec3(1, 0, 0), ax)), b = cross(ax, t);
                        wi = t * l.x + b * l.y + ax * l.z;
                    }
                    const double pdf = 0.5 * cosineHemispherePdf(wi) + 0.5 * phongLobePdf(dot(r, wi), n);
                    x = wi.z > 0 && pdf > 0 ? evalPhong(m, wo, wi).x * wi.z * env.radiance(wi) / pdf : 0.0;
                }
                const auto s = test::meanAndError(v);
                const double exact = exactReflected(env, 0.4, 0.5, n, wo);
                EXPECT_NEAR(s.mean, exact, 4 * s.stdError) << name << " n " << n << " theta " << deg;
            }
}

TEST(Environments, UnknownNameListsTheValidOnes) {
    try {
        makeEnvironment("sky");
        FAIL();
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("constant, gradient, disk, band, halfspace"), std::string::npos);
    }
}

namespace {

/// Unbiasedness at one shading point, with the error bar taken from 16 independent furnace runs (their
/// spread), not from the furnace's own standard error or z: |t| below the 4-sigma tail of Student's t
/// with 15 degrees of freedom.
void expectUnbiased(const std::string& estimator, const std::string& envName, double n, double theta, int repeats,
                    const EstimatorOptions& options = {}) {
    constexpr int kRuns = 16;
    FurnaceSetup s;
    s.estimator = estimator;
    s.options = options;
    s.rhoD = 0.3;
    s.rhoS = 0.6;
    s.n = n;
    s.thetaDeg = theta;
    s.phiDeg = 17;
    s.repeats = repeats / kRuns;
    const Environment env = makeEnvironment(envName);
    std::vector<double> estimates;
    double exact = 0;
    for (int run = 0; run < kRuns; ++run) {
        s.seed = mixSeed(1000 + static_cast<std::uint64_t>(n) + static_cast<std::uint64_t>(theta), static_cast<std::uint64_t>(run));
        const FurnaceResult r = runFurnace(s, env);
        estimates.push_back(r.estimate);
        exact = r.exact;
        s.knownExact = exact;  // its quadrature once per cell, not once per run
    }
    const auto m = test::meanAndError(estimates);
    const double t = m.stdError > 0 ? (m.mean - exact) / m.stdError : (m.mean == exact ? 0.0 : INFINITY);
    EXPECT_LT(std::abs(t), studentCritical(kRuns - 1))
        << fmt::format("{} (N' = {}, {}) on {}: n {} theta {}: {} +- {} vs exact {} (t = {:.2f})", estimator, options.symmetricN,
                       symmetricModeName(options.symmetricMode), envName, n, theta, m.mean, m.stdError, exact, t);
}

}  // namespace

class SymmetricUnbiased : public ::testing::TestWithParam<std::string> {};

TEST_P(SymmetricUnbiased, OnTheWholeFurnaceGrid) {
    for (double n : {1.0, 10.0, 100.0, 1000.0, 10000.0})
        for (double theta : {0.0, 30.0, 60.0, 85.0}) expectUnbiased(GetParam(), "constant", n, theta, 6000);
}

TEST_P(SymmetricUnbiased, OnEveryEnvironment) {
    for (const std::string& env : environmentNames())
        for (double n : {1.0, 100.0})
            for (double theta : {10.0, 60.0}) expectUnbiased(GetParam(), env, n, theta, 6000);
}

// --symmetric-n: N' points per piece, in both modes (spread mode spreads N' x P entries over a round).
TEST_P(SymmetricUnbiased, WithSeveralPointsPerPiece) {
    for (int nPrime : {2, 3})
        for (SymmetricMode mode : {SymmetricMode::Branch, SymmetricMode::Spread}) {
            EstimatorOptions o;
            o.symmetricN = nPrime;
            o.symmetricMode = mode;
            for (const char* env : {"constant", "disk"}) expectUnbiased(GetParam(), env, 10.0, 30.0, 4000, o);
        }
}

INSTANTIATE_TEST_SUITE_P(Corrected, SymmetricUnbiased, ::testing::Values("symmetric", "symmetric-shifted"), [](const auto& info) {
    return info.param == "symmetric" ? std::string("symmetric") : std::string("symmetric_shifted");
});

TEST(SymmetricDiffuse, ConstantRadianceGivesZeroVariance) {
    // Maps uniform in projected solid angle: every direction weighs rho_d Phi_piece / pi, 16 of them sum to rho_d.
    FurnaceSetup s;
    s.estimator = "symmetric";
    s.rhoD = 0.7;
    s.rhoS = 0.0;
    s.repeats = 100;
    for (const char* name : {"symmetric", "symmetric-shifted"}) {
        s.estimator = name;
        const FurnaceResult r = runFurnace(s, makeEnvironment("constant"));
        EXPECT_NEAR(r.estimate, 0.7, 1e-12) << name;
        EXPECT_LT(r.variance, 1e-24) << name;
        EXPECT_DOUBLE_EQ(r.directionsPerEstimate, 16.0) << name;
    }
}

TEST(PaperEstimator, IsFlaggedAsBiasedOnTheConstantEnvironment) {
    FurnaceSetup s;
    s.estimator = "paper";
    s.repeats = 4000;
    const FurnaceResult r = runFurnace(s, makeEnvironment("constant"));
    EXPECT_GT(std::abs(r.z), 10.0);
    EXPECT_LT(r.relativeBias, -0.2);
    // --paper-refined scales the specular part by the ratio of the two normalisations: with no diffuse
    // part and the same samples, the estimates are in exactly that ratio.
    s.rhoD = 0.0;
    s.n = 2;
    const double plain = runFurnace(s, makeEnvironment("constant")).estimate;
    s.options.paperRefined = true;
    const double refined = runFurnace(s, makeEnvironment("constant")).estimate;
    const double ratio = PaperEstimator::lobeNormalisation(2, true) / PaperEstimator::lobeNormalisation(2, false);
    EXPECT_LT(ratio, 0.95);
    EXPECT_NEAR(refined / plain, ratio, 1e-12);
}

TEST(Furnace, ShiftedCopiesReduceVarianceOnTheGradientSky) {
    // Not a timing: the variance of one estimate with the same number of directions.
    FurnaceSetup s;
    s.repeats = 4000;
    s.estimator = "symmetric";
    const double plain = runFurnace(s, makeEnvironment("gradient")).variance;
    s.estimator = "symmetric-shifted";
    const double shifted = runFurnace(s, makeEnvironment("gradient")).variance;
    EXPECT_LT(shifted, plain);
}
