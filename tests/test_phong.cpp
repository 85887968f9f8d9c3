// The normalised modified Phong BRDF: reciprocity, energy conservation, and the exact lobe integral
// against independent Monte Carlo estimates.
#include "materials/phong.h"
#include "sampling/warp.h"
#include "stats.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace symphong;

namespace {

PhongMaterial glossy(double kd, double ks, double n) {
    PhongMaterial m;
    m.rhoD = Color(kd);
    m.rhoS = Color(ks);
    m.exponent = n;
    return m;
}

Vec3 dirAt(double thetaDeg, double phiDeg) { return sphericalDirection(std::cos(thetaDeg * kPi / 180), phiDeg * kPi / 180); }

}  // namespace

TEST(Phong, IsReciprocal) {
    Rng rng(7, 1);
    for (double n : {1.0, 10.0, 100.0}) {
        const PhongMaterial m = glossy(0.3, 0.6, n);
        for (int i = 0; i < 2000; ++i) {
            const Vec3 a = sampleUniformHemisphere(rng.uniform2());
            const Vec3 b = sampleUniformHemisphere(rng.uniform2());
            const Color fab = evalPhong(m, a, b), fba = evalPhong(m, b, a);
            EXPECT_NEAR(fab.x, fba.x, 1e-12 * std::max(1.0, fab.x));
        }
    }
}

TEST(Phong, IsZeroBelowTheSurface) {
    const PhongMaterial m = glossy(0.5, 0.5, 10);
    EXPECT_TRUE(isBlack(evalPhong(m, Vec3(0, 0, 1), Vec3(0, 0.6, -0.8))));
    EXPECT_TRUE(isBlack(evalPhong(m, Vec3(0, 0.6, -0.8), Vec3(0, 0, 1))));
}

TEST(Phong, LobeIntegralAtNormalIncidenceIsTwoPiOverNPlusTwo) {
    for (double n : {0.0, 1.0, 10.0, 100.0, 1000.0, 10000.0})
        EXPECT_NEAR(phongLobeCosineIntegral(n, 0.0), kTwoPi / (n + 2.0), 1e-9 * kTwoPi / (n + 2.0)) << "n = " << n;
}

TEST(Phong, LobeIntegralDecreasesAsTheHorizonCutsTheLobe) {
    for (double n : {1.0, 10.0, 100.0}) {
        double previous = phongLobeCosineIntegral(n, 0.0);
        for (double deg : {30.0, 60.0, 85.0}) {
            const double v = phongLobeCosineIntegral(n, deg * kPi / 180);
            EXPECT_LT(v, previous) << "n = " << n << " theta = " << deg;
            previous = v;
        }
    }
}

// Independent check of the quadrature: Monte Carlo with lobe sampling (an unbiased estimate of the same
// integral: cos(theta') / ((n+1)/(2 pi)) for lobe directions above the horizon), within 4 standard errors.
TEST(Phong, LobeIntegralMatchesMonteCarlo) {
    Rng rng(11, 2);
    for (double n : {1.0, 10.0, 100.0, 1000.0})
        for (double deg : {30.0, 60.0, 85.0}) {
            const double theta = deg * kPi / 180;
            const Vec3 axis(std::sin(theta), 0, std::cos(theta));
            const Vec3 t(std::cos(theta), 0, -std::sin(theta)), b(0, 1, 0);
            std::vector<double> values(200000);
            for (double& v : values) {
                const Vec3 l = samplePhongLobe(rng.uniform2(), n);
                const Vec3 w = t * l.x + b * l.y + axis * l.z;
                v = w.z > 0 ? w.z * kTwoPi / (n + 1.0) : 0.0;
            }
            const auto s = test::meanAndError(values);
            const double exact = phongLobeCosineIntegral(n, theta);
            EXPECT_NEAR(s.mean, exact, 4 * s.stdError + 1e-12) << "n = " << n << " theta = " << deg;
        }
}

// Energy conservation: with rho_d + rho_s = 1 the directional albedo never exceeds 1, and it equals the
// Monte Carlo integral of f cos over the hemisphere (uniform sampling: independent of the BRDF's shape).
TEST(Phong, DirectionalAlbedoIsAtMostOneAndMatchesMonteCarlo) {
    Rng rng(5, 3);
    for (double n : {0.0, 1.0, 10.0, 100.0})
        for (double deg : {0.0, 30.0, 60.0, 85.0}) {
            const PhongMaterial m = glossy(0.4, 0.6, n);
            const Vec3 wo = dirAt(deg, 0);
            const double albedo = phongDirectionalAlbedo(m, wo).x;
            EXPECT_LE(albedo, 1.0 + 1e-12);
            std::vector<double> values(200000);
            for (double& v : values) {
                const Vec3 wi = sampleUniformHemisphere(rng.uniform2());
                v = evalPhong(m, wo, wi).x * wi.z * kTwoPi;
            }
            const auto s = test::meanAndError(values);
            EXPECT_NEAR(s.mean, albedo, 4 * s.stdError) << "n = " << n << " theta = " << deg;
        }
}

TEST(Phong, ValidationRejectsNonFiniteAndNegativeValues) {
    PhongMaterial m = glossy(0.5, 0.2, 10);
    m.rhoD.y = std::nan("");
    EXPECT_THROW(validateAndClampPhong(m), std::invalid_argument);
    m = glossy(0.5, 0.2, -1);
    EXPECT_THROW(validateAndClampPhong(m), std::invalid_argument);
    m = glossy(0.5, -0.2, 1);
    EXPECT_THROW(validateAndClampPhong(m), std::invalid_argument);
}

TEST(Phong, ValidationClampsAlbedoAboveOne) {
    PhongMaterial m = glossy(0.8, 0.6, 10);
    EXPECT_TRUE(validateAndClampPhong(m));
    EXPECT_NEAR(m.rhoD.x + m.rhoS.x, 1.0, 1e-12);
    EXPECT_NEAR(m.rhoD.x / m.rhoS.x, 0.8 / 0.6, 1e-12);
    PhongMaterial ok = glossy(0.5, 0.5, 10);
    EXPECT_FALSE(validateAndClampPhong(ok));
}
