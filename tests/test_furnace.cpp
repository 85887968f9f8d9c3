// The single-point furnace: exact values of every environment checked independently, `symmetric` and
// `symmetric-shifted` unbiased (within 4 standard errors) on the whole furnace grid and on every
// environment, and the `paper` estimator's bias detected.
#include "materials/phong.h"
#include "sampling/warp.h"
#include "stats.h"
#include "study/environment.h"
#include "study/furnace.h"

#include <gtest/gtest.h>

#include <fmt/format.h>

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

void expectUnbiased(const std::string& estimator, const std::string& envName, double n, double theta, int repeats) {
    FurnaceSetup s;
    s.estimator = estimator;
    s.rhoD = 0.3;
    s.rhoS = 0.6;
    s.n = n;
    s.thetaDeg = theta;
    s.phiDeg = 17;
    s.repeats = repeats;
    s.seed = 1000 + static_cast<std::uint64_t>(n) + static_cast<std::uint64_t>(theta);
    const FurnaceResult r = runFurnace(s, makeEnvironment(envName));
    EXPECT_LT(std::abs(r.z), 4.0) << fmt::format("{} on {}: n {} theta {}: {} +- {} vs exact {} (z = {:.2f})", estimator, envName, n,
                                                theta, r.estimate, r.stdError, r.exact, r.z);
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
    s.options.paperRefined = true;
    const FurnaceResult refined = runFurnace(s, makeEnvironment("constant"));
    EXPECT_NE(refined.estimate, r.estimate) << "the refined normalisation changes the specular part";
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
