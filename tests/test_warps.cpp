// Every warp: its pdf integrates to one, and its directions pass the chi-square goodness-of-fit test of
// tests/stats.h against that pdf over the whole sphere (docs/testing.md). Each TEST controls its family
// error: alpha = 0.01 over its runs (Sidak), an independent fixed seed per run. Densities that depend on
// an outgoing direction are tested at several.
#include "estimators/basic.h"
#include "math/branchless.h"
#include "math/frame.h"
#include "math/trig.h"
#include "sampling/alias_table.h"
#include "sampling/warp.h"
#include "sampling/warp_lanes.h"
#include "stats.h"
#include "test_util.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <limits>
#include <string>
#include <utility>

using namespace symphong;

namespace {

constexpr int kSamples = 400000;

std::vector<Vec3> draw(const std::function<Vec3(Rng&)>& sampler, std::uint64_t seed, int n = kSamples) {
    Rng rng(seed, 99);
    std::vector<Vec3> v(n);
    for (Vec3& w : v) w = sampler(rng);
    return v;
}

void expectFits(const std::string& what, const std::vector<Vec3>& dirs, const std::function<double(const Vec3&)>& pdf,
                const test::ChiSquareOptions& opts, int runs) {
    test::expectChiSquareFits(what, dirs, pdf, opts, runs);
}

test::ChiSquareOptions aroundAxis(const Vec3& axis, double concentration) {
    test::ChiSquareOptions o;
    o.axis = axis;
    o.concentration = concentration;
    return o;
}

}  // namespace

// The warps' sines and cosines (math/trig.h) against libm: over a fine grid of turns and of quarter-turn
// angles, the quarter-turn boundaries and the ends, within 4 units of roundoff of 1 (and sin^2 + cos^2 = 1
// as closely); the warps' directions, built from them, are checked against their pdfs below.
TEST(Trig, SinCosMatchLibmEverywhereTheWarpsAsk) {
    double worst = 0;
    const auto check = [&](double angle, SinCos r) {
        worst = std::max({worst, std::abs(r.sin - std::sin(angle)), std::abs(r.cos - std::cos(angle)),
                          std::abs(r.sin * r.sin + r.cos * r.cos - 1.0)});
    };
    const int n = 1 << 20;
    for (int i = 0; i <= n; ++i) {
        const double v = static_cast<double>(i) / n;
        check(kTwoPi * v, sinCosTurn(v));
        const double x = (kPi / 4.0) * (2.0 * v - 1.0);
        check(x, sinCosQuarter(x));
    }
    for (double v : {0.125, 0.25, 0.375, 0.5, 0.625, 0.75, 0.875, 1.0}) {
        check(kTwoPi * v, sinCosTurn(v));
        check(kTwoPi * std::nextafter(v, 0.0), sinCosTurn(std::nextafter(v, 0.0)));
    }
    check(kTwoPi * kOneBelow, sinCosTurn(kOneBelow));
    EXPECT_LT(worst, 4.0 * 2.220446049250313e-16);
}

TEST(Warps, PdfsIntegrateToOne) {
    // Adaptive quadrature over the whole sphere (the chi-square grid's cells), and the midpoint rule.
    EXPECT_NEAR(test::SphereChiSquare(uniformHemispherePdf).pdfIntegral(), 1.0, 1e-8);
    EXPECT_NEAR(test::SphereChiSquare(cosineHemispherePdf).pdfIntegral(), 1.0, 1e-8);
    EXPECT_NEAR(test::integrateOverSphere(uniformHemispherePdf), 1.0, 1e-4);
    EXPECT_NEAR(test::integrateOverSphere(cosineHemispherePdf), 1.0, 1e-4);
    for (double n : {0.0, 1.0, 10.0, 100.0, 1000.0, 10000.0})
        EXPECT_NEAR(test::SphereChiSquare([n](const Vec3& w) { return phongLobePdf(w.z, n); }, aroundAxis(Vec3(0, 0, 1), n)).pdfIntegral(),
                    1.0, 1e-8)
            << "n = " << n;
}

TEST(Warps, UniformHemisphereFitsItsPdf) {
    expectFits("uniform", draw([](Rng& r) { return sampleUniformHemisphere(r.uniform2()); }, 1), uniformHemispherePdf, {}, 1);
}

TEST(Warps, CosineHemisphereFitsItsPdf) {
    expectFits("cosine", draw([](Rng& r) { return sampleCosineHemisphere(r.uniform2()); }, 2), cosineHemispherePdf, {}, 1);
}

TEST(Warps, PhongLobeFitsItsPdf) {
    // Each lobe on a grid centred on its axis whose rows follow a lobe of its exponent (no partial grid).
    const std::vector<double> exponents = {0.0, 1.0, 10.0, 100.0, 1000.0, 10000.0};
    std::uint64_t seed = 300;
    for (double n : exponents)
        expectFits(
            "n = " + std::to_string(static_cast<int>(n)), draw([n](Rng& r) { return samplePhongLobe(r.uniform2(), n); }, seed++),
            [n](const Vec3& w) { return phongLobePdf(w.z, n); }, aroundAxis(Vec3(0, 0, 1), n), static_cast<int>(exponents.size()));
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

// The concentric map against its textbook form (Shirley and Chiu 1997, with pbrt's polar angles): for
// |a| > |b| the radius a at phi = pi/4 (b/a), else the radius b at phi = pi/2 - pi/4 (a/b), (r cos phi,
// r sin phi) by libm: on a grid over the square that includes its diagonals |a| = |b| (where the second
// case holds), the axes and the corners; within 4 units of roundoff.
TEST(Warps, ConcentricDiskIsShirleyChiusMap) {
    const auto textbook = [](Point2 p) {
        const double a = 2.0 * p.u - 1.0, b = 2.0 * p.v - 1.0;
        if (a == 0 && b == 0) return Point2{0, 0};
        const bool alongX = std::abs(a) > std::abs(b);
        const double r = alongX ? a : b, phi = alongX ? kPi / 4.0 * (b / a) : kPi / 2.0 - kPi / 4.0 * (a / b);
        return Point2{r * std::cos(phi), r * std::sin(phi)};
    };
    constexpr int n = 512;  // a multiple of 2: the grid holds u = 1/2 (a = 0) and the diagonals
    double worst = 0;
    int diagonal = 0;
    for (int i = 0; i <= n; ++i)
        for (int j = 0; j <= n; ++j) {
            const Point2 p{std::min(static_cast<double>(i) / n, kOneBelow), std::min(static_cast<double>(j) / n, kOneBelow)};
            const Point2 got = sampleConcentricDisk(p), want = textbook(p);
            worst = std::max({worst, std::abs(got.u - want.u), std::abs(got.v - want.v)});
            diagonal += std::abs(2.0 * p.u - 1.0) == std::abs(2.0 * p.v - 1.0);
        }
    EXPECT_GT(diagonal, n);  // both diagonals were on the grid
    EXPECT_LT(worst, 4.0 * 2.220446049250313e-16);
}

// math/branchless.h: choose, negateIf and clampByMasks give the branch's (std::clamp's) value bit for bit,
// for every kind of double (signed zeros, subnormals, infinities, NaNs with their payloads).
TEST(Branchless, ChooseNegateIfAndClampGiveTheBranchesBits) {
    const double values[] = {0.0,
                             -0.0,
                             1.0,
                             -2.5,
                             std::numeric_limits<double>::denorm_min(),
                             -std::numeric_limits<double>::min(),
                             std::numeric_limits<double>::max(),
                             std::numeric_limits<double>::infinity(),
                             -std::numeric_limits<double>::infinity(),
                             std::numeric_limits<double>::quiet_NaN(),
                             std::bit_cast<double>(std::uint64_t{0xfff4000000000123ull})};
    const auto bits = [](double x) { return std::bit_cast<std::uint64_t>(x); };
    for (const bool c : {false, true})
        for (const double x : values) {
            EXPECT_EQ(bits(negateIf(c, x)), bits(c ? -x : x)) << c << " " << x;
            for (const double y : values) EXPECT_EQ(bits(choose(c, x, y)), bits(c ? x : y)) << c << " " << x << " " << y;
        }
    for (const double v : values)
        for (const auto& [lo, hi] : {std::pair{-1.0, 1.0}, std::pair{0.05, 8.0}, std::pair{0.0, 0.0}, std::pair{-0.0, 2.5}})
            EXPECT_EQ(bits(clampByMasks(v, lo, hi)), bits(std::clamp(v, lo, hi))) << v << " in [" << lo << ", " << hi << "]";
}

TEST(Warps, UniformTriangleIsUniform) {
    // Barycentrics (b0, b1) cut into the k^2 congruent sub-triangles of a k x k subdivision: each holds
    // 1/k^2 of the samples; the half-squares of the k x k grid outside the triangle expect 0 (a sample
    // outside the triangle lands there and fails).
    constexpr int k = 12;
    std::vector<double> observed(2 * k * k, 0.0), expected(2 * k * k, 0.0);
    for (int i = 0; i < k; ++i)
        for (int j = 0; i + j < k; ++j) {
            expected[2 * (i * k + j)] = double(kSamples) / (k * k);
            if (i + j + 1 < k) expected[2 * (i * k + j) + 1] = double(kSamples) / (k * k);
        }
    Rng rng(6, 6);
    for (int n = 0; n < kSamples; ++n) {
        const Point2 b = sampleUniformTriangle(rng.uniform2());
        const double x = b.u * k, y = b.v * k;
        const int i = std::clamp(static_cast<int>(x), 0, k - 1), j = std::clamp(static_cast<int>(y), 0, k - 1);
        const bool upper = (x - i) + (y - j) >= 1.0;
        observed[2 * (i * k + j) + upper] += 1;
    }
    const auto r = test::chiSquareCounts(observed, expected, test::sidakAlpha(1));
    EXPECT_TRUE(r.passed) << r.describe();
    EXPECT_EQ(r.dof, k * k - 1);
}

TEST(Warps, AliasTableFollowsItsWeights) {
    const std::vector<double> w = {1.0, 0.0, 3.0, 6.0};
    const AliasTable d(w);
    EXPECT_DOUBLE_EQ(d.pmf(0), 0.1);
    EXPECT_DOUBLE_EQ(d.pmf(1), 0.0);
    Rng rng(8, 8);
    std::vector<double> counts(4, 0.0), expected(4, 0.0);
    double remapped = 0;
    for (int i = 0; i < kSamples; ++i) ++counts[d.sample(rng.uniform(), remapped)];
    for (int k = 0; k < 4; ++k) expected[k] = kSamples * w[k] / 10.0;  // from the weights, not from d.pmf
    const auto r = test::chiSquareCounts(counts, expected, test::sidakAlpha(1));
    EXPECT_TRUE(r.passed) << r.describe();  // fails on any sample of the zero-weight entry
    EXPECT_EQ(counts[1], 0);
}

// The Phong mixture's directions against the density it reports, at several outgoing directions
// (theta_o 0, 30, 60, 85 degrees, two azimuths) and exponents, each on two grids: one about the normal
// (the diffuse lobe and the horizon) and one about the mirror direction with rows that follow the lobe.
TEST(EstimatorDirections, PhongMixtureFitsItsPdf) {
    struct Wo {
        double thetaDeg, phi;
    };
    // Sanitized (test::kSanitized): three of the seven outgoing directions (normal, oblique, grazing),
    // every exponent and both grids, each at the full sample count; the level below follows the runs made.
    const std::vector<Wo> wos = test::kSanitized ? std::vector<Wo>{{0, 0}, {60, 4.0}, {85, 0.3}}
                                                 : std::vector<Wo>{{0, 0}, {30, 0.3}, {30, 2.2}, {60, 0.3}, {60, 4.0}, {85, 0.3}, {85, 5.1}};
    struct Mat {
        double rhoD, rhoS, n;
    };
    const std::vector<Mat> mats = {{0.3, 0.6, 5}, {0.5, 0.4, 50}, {0.2, 0.7, 1000}, {0.0, 0.9, 20}};
    const int runs = static_cast<int>(wos.size() * mats.size()) * 2;
    std::uint64_t seed = 900;
    for (const Wo& o : wos)
        for (const Mat& mt : mats) {
            PhongMaterial m;
            m.rhoD = Color(mt.rhoD);
            m.rhoS = Color(mt.rhoS);
            m.exponent = mt.n;
            const double t = o.thetaDeg * kPi / 180;
            const ShadingContext ctx{sphericalDirection(std::cos(t), o.phi), &m, 1, false};
            const Vec3 mirror(-ctx.wo.x, -ctx.wo.y, ctx.wo.z);
            const auto sample = [&](Rng& r) { return PhongLobeEstimator::sampleDirection(ctx, r.uniform2()); };
            const auto pdf = [&](const Vec3& w) { return PhongLobeEstimator::directionPdf(ctx, w); };
            char what[120];
            std::snprintf(what, sizeof what, "theta_o = %g deg, phi_o = %g, rho_d = %g, rho_s = %g, n = %g", o.thetaDeg, o.phi, mt.rhoD,
                          mt.rhoS, mt.n);
            expectFits(std::string(what) + ", grid about the normal", draw(sample, seed++, 200000), pdf, {}, runs);
            expectFits(std::string(what) + ", grid about the mirror direction", draw(sample, seed++, 200000), pdf, aroundAxis(mirror, mt.n),
                       runs);
        }
}

// The same test has power: a mixture density whose diffuse probability is 2% off (still normalised)
// is rejected at theta_o = 60 degrees on the normal's grid, with the same sample count, far below the
// per-run level of the 56 runs above (p = 3e-8 against 1.8e-4).
TEST(EstimatorDirections, PhongMixtureTestRejectsAWrongLobeProbability) {
    PhongMaterial m;
    m.rhoD = Color(0.5);
    m.rhoS = Color(0.4);
    m.exponent = 50;
    const ShadingContext ctx{sphericalDirection(0.5, 0.3), &m, 1, false};
    const double pd = PhongLobeEstimator::diffuseProbability(m) + 0.02;
    const Vec3 mirror(-ctx.wo.x, -ctx.wo.y, ctx.wo.z);
    const auto wrong = [&](const Vec3& w) { return pd * cosineHemispherePdf(w) + (1 - pd) * phongLobePdf(dot(mirror, w), m.exponent); };
    const auto r =
        test::chiSquareSphere(draw([&](Rng& g) { return PhongLobeEstimator::sampleDirection(ctx, g.uniform2()); }, 999, 200000), wrong);
    EXPECT_FALSE(r.passed) << r.describe();
    EXPECT_LT(r.pValue, test::sidakAlpha(56) / 100) << r.describe();
}

// sampling/warp_lanes.h: many points' cosine-hemisphere directions at once, in vector lanes where the processor has
// them, against sampleCosineHemisphere one point at a time: equal bit for bit, at random points, at the points
// where the concentric map changes case or divides by zero (the centre, the diagonals |a| = |b|, the square's
// edges and corners), and for counts that leave a part of a lane group empty.
TEST(WarpLanes, CosineHemisphereEqualsTheScalarWarpBitForBit) {
    Rng rng(43, 5);
    std::vector<double> us, vs;
    const std::vector<double> edges = {0.0, 0.5, kOneBelow, 0.25, 0.75, 1e-300, 0.5 + 1e-16, 0.5 - 1e-16, 0.125, 0.875};
    for (double u : edges)
        for (double v : edges) {
            us.push_back(u);
            vs.push_back(v);
        }
    for (int i = 0; i < 20000; ++i) {
        const double u = rng.uniform();
        us.push_back(u);
        vs.push_back(rng.uniform());
        us.push_back(u);  // on a diagonal of the square: |a| = |b|
        vs.push_back(i % 2 ? u : 1.0 - u);
    }
    const bool lanes = warpLanesAvailable();
    if (!lanes) std::printf("[ NOTE     ] no AVX-512 here: the dispatching call runs the scalar form\n");
    std::size_t checked = 0;
    for (std::size_t n : {std::size_t{0}, std::size_t{1}, std::size_t{7}, std::size_t{8}, std::size_t{13}, us.size()}) {
        std::vector<Vec3> viaCall(n), viaLanes(n);
        cosineHemisphereDirections(us.data(), vs.data(), n, viaCall.data());
        if (lanes) detail::cosineHemisphereDirectionsLanes(us.data(), vs.data(), n, viaLanes.data());
        for (std::size_t i = 0; i < n; ++i) {
            const Vec3 w = sampleCosineHemisphere({us[i], vs[i]});
            const auto same = [&](const Vec3& x) {
                return std::bit_cast<std::uint64_t>(x.x) == std::bit_cast<std::uint64_t>(w.x) &&
                       std::bit_cast<std::uint64_t>(x.y) == std::bit_cast<std::uint64_t>(w.y) &&
                       std::bit_cast<std::uint64_t>(x.z) == std::bit_cast<std::uint64_t>(w.z);
            };
            ASSERT_TRUE(same(viaCall[i])) << "point " << i << " of " << n << ": u " << us[i] << " v " << vs[i];
            if (lanes) {
                ASSERT_TRUE(same(viaLanes[i])) << "lanes, point " << i << " of " << n << ": u " << us[i] << " v " << vs[i];
            }
            ++checked;
        }
    }
    EXPECT_EQ(checked, 1 + 7 + 8 + 13 + us.size());
}
