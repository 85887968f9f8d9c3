// Every warp: its pdf integrates to one, and its directions pass a chi-square goodness-of-fit test
// against that pdf (significance 1e-3 each, fixed seeds).
#include "estimators/basic.h"
#include "sampling/distribution1d.h"
#include "sampling/warp.h"
#include "stats.h"

#include <gtest/gtest.h>

#include <functional>

using namespace symphong;

namespace {

constexpr double kAlpha = 1e-3;
constexpr int kSamples = 400000;

std::vector<Vec3> draw(const std::function<Vec3(Rng&)>& sampler, std::uint64_t seed) {
    Rng rng(seed, 99);
    std::vector<Vec3> v(kSamples);
    for (Vec3& w : v) w = sampler(rng);
    return v;
}

void expectFits(const std::vector<Vec3>& dirs, const std::function<double(const Vec3&)>& pdf, int thetaRes, int phiRes,
                double thetaMax = kPi) {
    const auto r = test::chiSquareDirections(dirs, pdf, thetaRes, phiRes, thetaMax);
    EXPECT_GT(r.pValue, kAlpha) << r.describe();
    EXPECT_GT(r.dof, 10) << "too few cells to be a meaningful test: " << r.describe();
}

}  // namespace

TEST(Warps, PdfsIntegrateToOne) {
    EXPECT_NEAR(test::integrateOverSphere(uniformHemispherePdf), 1.0, 1e-4);
    EXPECT_NEAR(test::integrateOverSphere(cosineHemispherePdf), 1.0, 1e-4);
    for (double n : {0.0, 1.0, 10.0, 100.0})
        EXPECT_NEAR(test::integrateOverSphere([n](const Vec3& w) { return phongLobePdf(w.z, n); }, 20000, 16), 1.0, 1e-4)
            << "n = " << n;
}

TEST(Warps, UniformHemisphereFitsItsPdf) {
    expectFits(draw([](Rng& r) { return sampleUniformHemisphere(r.uniform2()); }, 1), uniformHemispherePdf, 20, 40);
}

TEST(Warps, CosineHemisphereFitsItsPdf) {
    expectFits(draw([](Rng& r) { return sampleCosineHemisphere(r.uniform2()); }, 2), cosineHemispherePdf, 20, 40);
}

TEST(Warps, PhongLobeFitsItsPdf) {
    // The grid covers the lobe's core (where the samples are) finely; the rest is one pooled cell.
    for (double n : {1.0, 10.0, 100.0, 1000.0}) {
        const double thetaMax = std::min(kPi, 6.0 / std::sqrt(n + 1.0));
        expectFits(draw([n](Rng& r) { return samplePhongLobe(r.uniform2(), n); }, 3),
                   [n](const Vec3& w) { return phongLobePdf(w.z, n); }, 24, 32, thetaMax);
    }
}

TEST(Warps, ConcentricDiskStaysInTheDiskAndIsUniform) {
    Rng rng(4, 4);
    int inner = 0;
    for (int i = 0; i < kSamples; ++i) {
        const Point2 d = sampleConcentricDisk(rng.uniform2());
        ASSERT_LE(d.u * d.u + d.v * d.v, 1.0 + 1e-12);
        inner += (d.u * d.u + d.v * d.v < 0.25);
    }
    // The inner disk of radius 1/2 holds a quarter of the area: binomial standard error.
    const double p = static_cast<double>(inner) / kSamples, se = std::sqrt(0.25 * 0.75 / kSamples);
    EXPECT_NEAR(p, 0.25, 4 * se);
}

TEST(Warps, UniformTriangleIsUniform) {
    // Barycentrics are uniform on the triangle iff each of the 4 midpoint sub-triangles gets 1/4.
    Rng rng(6, 6);
    int counts[4] = {0, 0, 0, 0};
    for (int i = 0; i < kSamples; ++i) {
        const Point2 b = sampleUniformTriangle(rng.uniform2());
        const double b2 = 1.0 - b.u - b.v;
        ASSERT_GE(b2, -1e-12);
        const int k = b.u > 0.5 ? 0 : (b.v > 0.5 ? 1 : (b2 > 0.5 ? 2 : 3));
        ++counts[k];
    }
    double chi2 = 0;
    for (int c : counts) chi2 += (c - kSamples / 4.0) * (c - kSamples / 4.0) / (kSamples / 4.0);
    EXPECT_GT(test::gammaQ(1.5, 0.5 * chi2), kAlpha) << "chi2 = " << chi2;
}

TEST(Warps, Distribution1DFollowsItsWeights) {
    const std::vector<double> w = {1.0, 0.0, 3.0, 6.0};
    const Distribution1D d(w);
    EXPECT_DOUBLE_EQ(d.pmf(0), 0.1);
    EXPECT_DOUBLE_EQ(d.pmf(1), 0.0);
    Rng rng(8, 8);
    int counts[4] = {0, 0, 0, 0};
    for (int i = 0; i < kSamples; ++i) ++counts[d.sample(rng.uniform())];
    EXPECT_EQ(counts[1], 0);
    double chi2 = 0;
    for (int k : {0, 2, 3}) chi2 += std::pow(counts[k] - kSamples * d.pmf(k), 2) / (kSamples * d.pmf(k));
    EXPECT_GT(test::gammaQ(1.0, 0.5 * chi2), kAlpha) << "chi2 = " << chi2;
}

// The estimators' own direction distributions against the densities they report.
TEST(EstimatorDirections, PhongMixtureFitsItsPdf) {
    for (double deg : {0.0, 45.0, 80.0})
        for (double n : {5.0, 50.0}) {
            PhongMaterial m;
            m.rhoD = Color(0.3);
            m.rhoS = Color(0.6);
            m.exponent = n;
            const ShadingContext ctx{sphericalDirection(std::cos(deg * kPi / 180), 0.3), &m, 1, false};
            expectFits(draw([&](Rng& r) { return PhongLobeEstimator::sampleDirection(ctx, r.uniform2()); }, 9),
                       [&](const Vec3& w) { return PhongLobeEstimator::directionPdf(ctx, w); }, 40, 48);
        }
}

// The chi-square test must have power: it rejects directions drawn from a slightly different density.
TEST(ChiSquare, RejectsAWrongDensity) {
    const auto cosine = draw([](Rng& r) { return sampleCosineHemisphere(r.uniform2()); }, 12);
    EXPECT_LT(test::chiSquareDirections(cosine, uniformHemispherePdf, 20, 40).pValue, 1e-6);
    const auto lobe = draw([](Rng& r) { return samplePhongLobe(r.uniform2(), 100.0); }, 13);
    EXPECT_LT(test::chiSquareDirections(lobe, [](const Vec3& w) { return phongLobePdf(w.z, 110.0); }, 24, 32,
                                        6.0 / std::sqrt(101.0)).pValue,
              1e-6);
}
