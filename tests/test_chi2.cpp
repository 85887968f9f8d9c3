// The chi-square helper itself (tests/stats.h): its p-values, its pooling, its expected counts against
// closed forms, that it accepts correct samplers at about the nominal rate over independent seeds, and
// that it has power: it rejects each of the defects the old helper let through. Fixed seeds.
#include "math/frame.h"
#include "sampling/rng.h"
#include "sampling/warp.h"
#include "stats.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <vector>

using namespace symphong;
using test::ChiSquareOptions;
using test::ChiSquareResult;

namespace {

template <class F>
std::vector<Vec3> draw(std::size_t n, std::uint64_t seed, F&& sampler) {
    Rng rng(seed, 0x51);
    std::vector<Vec3> v(n);
    for (Vec3& w : v) w = sampler(rng);
    return v;
}

std::vector<Vec3> cosineSamples(std::size_t n, std::uint64_t seed) {
    return draw(n, seed, [](Rng& r) { return sampleCosineHemisphere(r.uniform2()); });
}

/// A Phong lobe cos^n about `axis`: sampler and density.
struct Lobe {
    Vec3 axis;
    double n;
    Frame frame = Frame::fromNormal(axis);
    Vec3 sample(Point2 u) const { return frame.toWorld(samplePhongLobe(u, n)); }
    double pdf(const Vec3& w) const { return phongLobePdf(dot(axis, w), n); }
};

ChiSquareOptions lobeGrid(const Vec3& axis, double n, double alpha = 0.01) {
    ChiSquareOptions o;
    o.axis = axis;
    o.concentration = n;
    o.alpha = alpha;
    return o;
}

/// log of e^-x x^k / k!, for the closed form of Q at integer a.
double logPoisson(double x, int k) { return -x + k * std::log(x) - std::lgamma(k + 1.0); }

}  // namespace

// ----------------------------------------------------------------------------------------------------
// p-values and the Sidak correction

TEST(ChiSquareHelper, GammaQMatchesClosedForms) {
    for (double x : {0.01, 0.5, 1.0, 3.0, 10.0, 40.0}) {
        EXPECT_NEAR(test::gammaQ(1.0, x), std::exp(-x), 1e-14 + 1e-12 * std::exp(-x)) << x;                        // chi2, 2 dof
        EXPECT_NEAR(test::gammaQ(0.5, x), std::erfc(std::sqrt(x)), 1e-14 + 1e-10 * std::erfc(std::sqrt(x))) << x;  // 1 dof
    }
    // Integer a at the sizes of our grids (dof ~ 880): Q(a, x) = sum_{k<a} e^-x x^k / k!.
    for (int a : {5, 60, 440})
        for (double f : {0.7, 0.95, 1.0, 1.05, 1.3}) {
            const double x = f * a;
            double q = 0;
            for (int k = 0; k < a; ++k) q += std::exp(logPoisson(x, k));
            EXPECT_NEAR(test::gammaQ(a, x), q, 1e-10 * q + 1e-300) << "a = " << a << ", x = " << x;
        }
    EXPECT_EQ(test::chiSquarePValue(std::numeric_limits<double>::infinity(), 10), 0.0);
    EXPECT_EQ(test::chiSquarePValue(std::nan(""), 10), 0.0);
}

TEST(ChiSquareHelper, SidakAlphaMakesTheFamilyLevelOnePercent) {
    EXPECT_NEAR(test::sidakAlpha(1), 0.01, 1e-15);
    for (int runs : {2, 8, 21, 56}) {
        const double a = test::sidakAlpha(runs);
        EXPECT_NEAR(1.0 - std::pow(1.0 - a, runs), 0.01, 1e-14) << runs;
        EXPECT_LT(a, 0.01 / runs * 1.01);
    }
    EXPECT_NEAR(test::sidakAlpha(21), 4.785e-4, 5e-7);
}

// ----------------------------------------------------------------------------------------------------
// Pooling and zero cells, on counts

TEST(ChiSquareHelper, PoolsSmallCellsAndAlwaysCountsThePool) {
    // Sorted: 0.5, 1, 2, 3 pool to 6.5 (counted); 4 starts a pool that takes 10 (14, counted); 20 and 100
    // stand alone; the zero cell without samples is ignored.
    const std::vector<double> expected = {10, 1, 0, 2, 100, 3, 20, 0.5, 4};
    std::vector<double> observed = expected;
    const auto r = test::chiSquareCounts(observed, expected, 0.01);
    EXPECT_EQ(r.zeroCells, 1);
    EXPECT_EQ(r.pooledCells, 6);
    EXPECT_EQ(r.pools, 2);
    EXPECT_EQ(r.dof, 3);  // terms: 6.5, 14, 20, 100
    EXPECT_NEAR(r.statistic, 0.0, 1e-12);
    EXPECT_TRUE(r.passed) << r.describe();

    // Samples moved into the smallest cell: the pool shows it (it is counted, not dropped).
    std::vector<double> shifted = expected;
    shifted[7] += 10;  // the 0.5 cell
    shifted[4] -= 10;  // from the 100 cell
    const auto s = test::chiSquareCounts(shifted, expected, 0.01);
    EXPECT_NEAR(s.statistic, 100.0 / 6.5 + 100.0 / 100.0, 1e-12);
    EXPECT_FALSE(s.passed) << s.describe();

    // A last pool that never reaches 5 is merged into the previous pool: 2+3 = 5 (counted), 3+3 = 6
    // (counted), then 3 alone is short: merged into the 6, so two terms, 5 and 9.
    const std::vector<double> small = {3, 3, 3, 3, 2};
    const std::vector<double> seen = {1, 0, 6, 5, 2};
    const auto m = test::chiSquareCounts(seen, small, 0.01);
    EXPECT_EQ(m.pooledCells, 5);
    EXPECT_EQ(m.pools, 2);
    EXPECT_EQ(m.dof, 1);
    // Terms, cells by sorted order: {4, 0} observed 3, expected 5; {1, 2, 3} observed 11, expected 9.
    EXPECT_NEAR(m.statistic, 4.0 / 5 + 4.0 / 9, 1e-12) << m.describe();

    // One sample in a zero cell fails, whatever the statistic.
    observed[2] = 1;
    observed[4] -= 1;
    const auto z = test::chiSquareCounts(observed, expected, 0.01);
    EXPECT_FALSE(z.passed);
    EXPECT_EQ(z.zeroCellSamples, 1u);
    EXPECT_NE(z.failure.find("integrates to 0"), std::string::npos) << z.describe();
}

// ----------------------------------------------------------------------------------------------------
// Expected counts: every cell's integral against its closed form

TEST(ChiSquareHelper, CellIntegralsMatchClosedForms) {
    // Uniform sphere density, any axis: every cell is 1/(R P) of the sphere (equal-area rows).
    for (const Vec3 axis : {Vec3(0, 0, 1), normalize(Vec3(1, 2, 3))}) {
        ChiSquareOptions o;
        o.axis = axis;
        const test::SphereChiSquare grid([](const Vec3&) { return 1.0 / (4 * kPi); }, o);
        for (int i = 0; i < grid.rows(); ++i)
            for (int j = 0; j < grid.cols(); ++j)
                ASSERT_NEAR(grid.cellProbability(i, j), 1.0 / (grid.rows() * grid.cols()), 1e-13) << i << " " << j;
    }
    // Cosine hemisphere about the normal: a row [z0, z1] holds (max(z1,0)^2 - max(z0,0)^2) / P; the middle
    // row straddles the horizon, where the density jumps to 0 (rows: z = 1 - 2i/R).
    {
        const test::SphereChiSquare grid(cosineHemispherePdf);
        const int R = grid.rows(), P = grid.cols();
        double total = 0;
        for (int i = 0; i < R; ++i) {
            const double z1 = std::max(0.0, 1.0 - 2.0 * i / R), z0 = std::max(0.0, 1.0 - 2.0 * (i + 1) / R);
            for (int j = 0; j < P; ++j) {
                ASSERT_NEAR(grid.cellProbability(i, j), (z1 * z1 - z0 * z0) / P, 1e-12) << i << " " << j;
                total += grid.cellProbability(i, j);
            }
        }
        EXPECT_GT(grid.cellProbability(R / 2, 0), 0.0) << "the straddling row holds the band just above the horizon";
        EXPECT_EQ(grid.cellProbability(R / 2 + 1, 0), 0.0);
        EXPECT_NEAR(grid.pdfIntegral(), 1.0, 1e-12);
        EXPECT_NEAR(total, 1.0, 1e-12);
    }
    // A Phong lobe about an oblique axis on its concentrated grid: a row holds (z1^(n+1) - z0^(n+1)) / P
    // of it (z clamped at 0), with rows equal in s = 1 - ((1+z)/2)^(c+1).
    for (double n : {10.0, 1000.0}) {
        const Lobe lobe{normalize(Vec3(-1, 2, 0.5)), n};
        const test::SphereChiSquare grid([&](const Vec3& w) { return lobe.pdf(w); }, lobeGrid(lobe.axis, n));
        const int R = grid.rows(), P = grid.cols();
        const auto zEdge = [&](int i) { return 2.0 * std::pow(1.0 - double(i) / R, 1.0 / (n + 1)) - 1.0; };
        for (int i = 0; i < R; ++i) {
            const double z1 = std::max(0.0, zEdge(i)), z0 = std::max(0.0, zEdge(i + 1));
            const double exact = (std::pow(z1, n + 1) - std::pow(z0, n + 1)) / P;
            for (int j = 0; j < P; j += 7) ASSERT_NEAR(grid.cellProbability(i, j), exact, 1e-10) << n << " " << i;
        }
        EXPECT_NEAR(grid.pdfIntegral(), 1.0, 1e-8);
        // The lobe is spread over the rows: the first row holds about 2/R of it, not all of it.
        EXPECT_LT(grid.cellProbability(0, 0) * P, 3.0 / R);
    }
}

TEST(ChiSquareHelper, RefusesAnEvenResolution) {
    ChiSquareOptions o;
    o.thetaRes = 20;
    EXPECT_THROW(test::SphereChiSquare(cosineHemispherePdf, o), std::invalid_argument);
}

// ----------------------------------------------------------------------------------------------------
// Correct samplers pass

TEST(ChiSquareHelper, AcceptsCorrectSamplers) {
    constexpr int kRuns = 3;
    const double alpha = test::sidakAlpha(kRuns);
    {
        ChiSquareOptions o;
        o.alpha = alpha;
        const auto r = test::chiSquareSphere(cosineSamples(1000000, 1), cosineHemispherePdf, o);
        EXPECT_TRUE(r.passed) << "cosine: " << r.describe();
        EXPECT_GT(r.dof, 400) << r.describe();
    }
    std::uint64_t seed = 2;
    for (double n : {10.0, 1000.0}) {
        const Lobe lobe{normalize(Vec3(0.3, -0.4, 0.8)), n};
        const auto dirs = draw(1000000, seed++, [&](Rng& r) { return lobe.sample(r.uniform2()); });
        const auto r = test::chiSquareSphere(
            dirs, [&](const Vec3& w) { return lobe.pdf(w); }, lobeGrid(lobe.axis, n, alpha));
        EXPECT_TRUE(r.passed) << "Phong n = " << n << ": " << r.describe();
        EXPECT_GT(r.dof, 400) << r.describe();
    }
}

// Over 20 independent seeds a correct sampler is rejected at alpha = 0.01 about once in 100 runs: no more
// rejections than Binomial(20, 0.01) allows at 1e-4 (3), and the statistic's mean is its dof (Pearson's
// statistic has expectation exactly cells - 1 under the null), within 4 standard errors of the 20 values.
TEST(ChiSquareHelper, RejectsCorrectSamplersAtTheNominalRate) {
    constexpr int kSeeds = 20;
    constexpr double kAlpha = 0.01;
    // Largest k with P(X >= k) > 1e-4 for X ~ Binomial(20, 0.01): the most rejections allowed.
    int allowed = 0;
    for (int k = 1; k <= kSeeds; ++k) {
        double tail = 0;
        for (int j = k; j <= kSeeds; ++j)
            tail += std::exp(std::lgamma(kSeeds + 1.0) - std::lgamma(j + 1.0) - std::lgamma(kSeeds - j + 1.0) + j * std::log(kAlpha) +
                             (kSeeds - j) * std::log1p(-kAlpha));
        if (tail > 1e-4) allowed = k;
    }
    ASSERT_EQ(allowed, 3);

    struct Case {
        const char* name;
        std::function<Vec3(Rng&)> sample;
        std::function<double(const Vec3&)> pdf;
        ChiSquareOptions opts;
    };
    const Lobe lobe{Vec3(0, 0, 1), 1000.0};
    const Lobe tilted{normalize(Vec3(0.8, 0.1, 0.2)), 20.0};  // a lobe that the horizon cuts, on the normal's grid
    std::vector<Case> cases = {
        {"cosine", [](Rng& r) { return sampleCosineHemisphere(r.uniform2()); }, cosineHemispherePdf, {}},
        {"uniform", [](Rng& r) { return sampleUniformHemisphere(r.uniform2()); }, uniformHemispherePdf, {}},
        {"Phong n = 1000", [&](Rng& r) { return lobe.sample(r.uniform2()); }, [&](const Vec3& w) { return lobe.pdf(w); },
         lobeGrid(lobe.axis, 1000.0)},
        {"tilted Phong n = 20", [&](Rng& r) { return tilted.sample(r.uniform2()); }, [&](const Vec3& w) { return tilted.pdf(w); }, {}},
    };
    std::uint64_t seed = 100;
    for (Case& c : cases) {
        c.opts.alpha = kAlpha;
        const test::SphereChiSquare grid(c.pdf, c.opts);
        int rejected = 0;
        std::vector<double> stats;
        int dof = -1;
        for (int s = 0; s < kSeeds; ++s) {
            const auto r = grid.test(draw(200000, seed++, c.sample));
            rejected += !r.passed;
            stats.push_back(r.statistic);
            if (dof >= 0) {
                ASSERT_EQ(r.dof, dof) << "the grouping must not depend on the samples";
            }
            dof = r.dof;
            ASSERT_EQ(r.zeroCellSamples, 0u) << c.name << ": " << r.describe();
        }
        EXPECT_LE(rejected, allowed) << c.name;
        const auto m = test::meanAndError(stats);
        if (std::getenv("SYMPHONG_CHI2_VERBOSE"))
            std::printf("%s: %d of %d rejected; mean statistic %.1f +- %.1f, dof %d, spread %.1f (sqrt(2 dof) = %.1f)\n", c.name, rejected,
                        kSeeds, m.mean, m.stdError, dof, m.stdError * std::sqrt(double(kSeeds)), std::sqrt(2.0 * dof));
        EXPECT_NEAR(m.mean, dof, 4 * m.stdError) << c.name << ": mean statistic over " << kSeeds << " seeds";
        // The spread is the chi-square's, sqrt(2 dof): the standard deviation of 20 values has a relative
        // standard error of 1/sqrt(2 x 19); 4 of them.
        EXPECT_NEAR(m.stdError * std::sqrt(double(kSeeds)), std::sqrt(2.0 * dof),
                    4.0 / std::sqrt(2.0 * (kSeeds - 1)) * std::sqrt(2.0 * dof))
            << c.name;
    }
}

// ----------------------------------------------------------------------------------------------------
// Power: each defect the old helper could not see

// A cosine sampler that reflects 0.1% of its directions below the horizon (z -> -z).
TEST(ChiSquareHelper, RejectsALeakOfOnePerMilleBelowTheHorizon) {
    std::uint64_t i = 0;
    const auto dirs = draw(1000000, 11, [&](Rng& r) {
        Vec3 w = sampleCosineHemisphere(r.uniform2());
        if (i++ % 1000 == 0) w.z = -w.z;
        return w;
    });
    const auto r = test::chiSquareSphere(dirs, cosineHemispherePdf);
    EXPECT_FALSE(r.passed) << r.describe();
    EXPECT_GT(r.zeroCellSamples, 900u) << r.describe();  // all but the ~1/R^2 that stay in the straddling row
    EXPECT_NE(r.failure.find("integrates to 0"), std::string::npos) << r.describe();
}

// Strict zero cells: one direction out of a million, well below the horizon, is enough.
TEST(ChiSquareHelper, RejectsASingleSampleWhereTheDensityIsZero) {
    auto dirs = cosineSamples(1000000, 12);
    dirs[12345] = normalize(Vec3(0.3, 0.2, -0.5));
    const auto r = test::chiSquareSphere(dirs, cosineHemispherePdf);
    EXPECT_FALSE(r.passed) << r.describe();
    EXPECT_EQ(r.zeroCellSamples, 1u) << r.describe();
}

// A density 1% too high everywhere: the samples are fine, the normalisation is not.
TEST(ChiSquareHelper, RejectsADensityScaledByOnePercent) {
    const auto r = test::chiSquareSphere(cosineSamples(1000000, 13), [](const Vec3& w) { return 1.01 * cosineHemispherePdf(w); });
    EXPECT_FALSE(r.passed) << r.describe();
    EXPECT_NEAR(r.pdfIntegral, 1.01, 1e-7);
    EXPECT_NE(r.failure.find("integrates to 1.01"), std::string::npos) << r.describe();
}

// A density 1% too high on one half of the hemisphere and 1% too low on the other (still normalised):
// only the statistic can see it.
TEST(ChiSquareHelper, RejectsADensityOffByOnePercentOnHalfTheSphere) {
    const auto pdf = [](const Vec3& w) { return cosineHemispherePdf(w) * (w.y >= 0 ? 1.01 : 0.99); };
    const auto r = test::chiSquareSphere(cosineSamples(4000000, 14), pdf);
    EXPECT_NEAR(r.pdfIntegral, 1.0, 1e-7);
    EXPECT_EQ(r.zeroCellSamples, 0u);
    EXPECT_FALSE(r.passed) << r.describe();
    EXPECT_LT(r.pValue, 1e-6) << r.describe();
}

// A Phong lobe sampled with n = 100 against the density of n = 105.
TEST(ChiSquareHelper, RejectsPhongHundredAgainstHundredAndFive) {
    const Lobe sampled{normalize(Vec3(0.2, 0.3, 1)), 100.0}, claimed{sampled.axis, 105.0};
    const auto dirs = draw(1000000, 15, [&](Rng& r) { return sampled.sample(r.uniform2()); });
    const auto r = test::chiSquareSphere(
        dirs, [&](const Vec3& w) { return claimed.pdf(w); }, lobeGrid(sampled.axis, 100.0));
    EXPECT_NEAR(r.pdfIntegral, 1.0, 1e-7);
    EXPECT_FALSE(r.passed) << r.describe();
    EXPECT_LT(r.pValue, 1e-12) << r.describe();
}

TEST(ChiSquareHelper, RejectsUniformSamplesAgainstTheCosineDensity) {
    const auto dirs = draw(1000000, 16, [](Rng& r) { return sampleUniformHemisphere(r.uniform2()); });
    const auto r = test::chiSquareSphere(dirs, cosineHemispherePdf);
    EXPECT_FALSE(r.passed) << r.describe();
    EXPECT_LT(r.pValue, 1e-12) << r.describe();
}

// Mass where no sample goes: the density claims 2% of its mass spread over the lower hemisphere (and is
// normalised), the samples are a plain lobe. The old partial grid put all of that in one leftover cell;
// here every lower cell expects samples and gets none.
TEST(ChiSquareHelper, RejectsMassClaimedWhereNoSampleGoes) {
    const Lobe lobe{Vec3(0, 0, 1), 10.0};
    const auto pdf = [&](const Vec3& w) { return 0.98 * lobe.pdf(w) + (w.z < 0 ? 0.02 / kTwoPi : 0.0); };
    const auto r = test::chiSquareSphere(draw(1000000, 17, [&](Rng& g) { return lobe.sample(g.uniform2()); }), pdf);
    EXPECT_NEAR(r.pdfIntegral, 1.0, 1e-7);
    EXPECT_FALSE(r.passed) << r.describe();
    EXPECT_LT(r.pValue, 1e-12) << r.describe();
}

TEST(ChiSquareHelper, RejectsDirectionsThatAreNotUnitVectors) {
    auto dirs = cosineSamples(100000, 18);
    dirs[7] = dirs[7] * 1.001;
    const auto r = test::chiSquareSphere(dirs, cosineHemispherePdf);
    EXPECT_FALSE(r.passed);
    EXPECT_EQ(r.badSamples, 1u) << r.describe();
}

// A density that is positive only on a sliver of a cell, which the first 4 x 4 split of the cell can
// miss: a sample there makes the helper integrate that cell again rather than call it a zero cell.
TEST(ChiSquareHelper, FindsASliverOfSupportThatHoldsASample) {
    // Uniform on a thin cap around a direction inside a cell, away from the cell's quadrature nodes.
    const Vec3 c = sphericalDirection(0.3, 0.0123);
    const double cosCap = std::cos(0.002);
    const double capArea = kTwoPi * (1 - cosCap);
    const auto pdf = [&](const Vec3& w) { return dot(w, c) >= cosCap ? 1.0 / capArea : 0.0; };
    const auto dirs = draw(2000, 19, [&](Rng& r) {
        const Point2 u = r.uniform2();
        return Frame::fromNormal(c).toWorld(sphericalDirection(1 - u.u * (1 - cosCap), kTwoPi * u.v));
    });
    ChiSquareOptions o;
    o.minDof = 0;
    const test::SphereChiSquare grid(pdf, o);
    EXPECT_LT(grid.pdfIntegral(), 0.5) << "the cap falls between the first quadrature nodes (else this tests nothing)";
    const auto r = grid.test(dirs);
    EXPECT_EQ(r.zeroCellSamples, 0u) << r.describe();
    EXPECT_NEAR(r.pdfIntegral, 1.0, 1e-4) << r.describe();
}
