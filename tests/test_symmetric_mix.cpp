// `symmetric-mix` (src/estimators/symmetric_mix.h) and its maps (src/sampling/separation.h): densities
// that integrate to one, chi-square of the directions against the density it reports for every material
// class (diffuse only, glossy only, mixed; n from 0 to 10^4), unbiasedness on the furnace grid in both
// modes and every orbit, and the white furnace: for a purely diffuse material every direction weighs
// exactly rho_d, so the variance of one camera sample is zero, as for cosine sampling (the bound: at
// most cosine's, which is zero). Fixed seeds; statistical tolerances from the estimators' own errors.
#include "estimators/basic.h"
#include "estimators/symmetric_mix.h"
#include "sample_util.h"
#include "sampling/separation.h"
#include "sampling/warp.h"
#include "stats.h"
#include "study/furnace.h"
#include "compare/metrics.h"

#include <gtest/gtest.h>

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

using namespace symphong;
using namespace symphong::separation;

namespace {

PhongMaterial material(double kd, double ks, double n) {
    PhongMaterial m;
    m.rhoD = Color(kd);
    m.rhoS = Color(ks);
    m.exponent = n;
    return m;
}

}  // namespace

// ---------------------------------------------------------------------------------------------------
// The maps

// Drawing the triangle with probability Phi_T / (pi/8) and each piece by its exact map is cosine
// sampling of the octant: with a random octant, cosine sampling of the hemisphere (chi-square against
// cos/pi, a density computed independently of the maps), and the triangle's share matches Lambert's.
TEST(SymmetricMixMaps, OctantCosineMapIsCosineSampling) {
    EXPECT_NEAR(kTriangleShare, 0.554126, 1e-6);
    Rng rng(5, 1);
    std::vector<Vec3> dirs;
    int triangles = 0;
    constexpr int kDraws = 200000;
    for (int i = 0; i < kDraws; ++i) {
        const Vec3 w = octantCosineMap(rng.uniform2());
        ASSERT_NEAR(length(w), 1.0, 1e-12);
        ASSERT_EQ(octantOf(w), 0) << w.x << " " << w.y;
        triangles += inTriangles(w) ? 1 : 0;
        dirs.push_back(toOctant(w, static_cast<int>(rng.uniform() * 8)));
    }
    const double share = static_cast<double>(triangles) / kDraws;
    EXPECT_NEAR(share, kTriangleShare, 4 * std::sqrt(kTriangleShare * (1 - kTriangleShare) / kDraws));
    const auto r = test::chiSquareSphere(dirs, [](const Vec3& w) { return cosineHemispherePdf(w); });
    EXPECT_TRUE(r.passed) << r.describe();
}

// The 8 wedges of the exact lobe cover all of it: with a random wedge, phongWedgeMap is Phong-lobe
// sampling about +Z, against (n+1)/(2 pi) cos^n (chi-square, grid concentrated on the lobe), n = 0..10^4.
TEST(SymmetricMixMaps, WedgesCoverTheWholeLobe) {
    const std::vector<double> ns = {0, 1, 10, 100, 1000, 10000};
    for (double n : ns) {
        Rng rng(11 + static_cast<std::uint64_t>(n), 3);
        std::vector<Vec3> dirs;
        for (int i = 0; i < 100000; ++i) {
            const Vec3 w = phongWedgeMap(rng.uniform2(), n);
            ASSERT_NEAR(length(w), 1.0, 1e-12);
            ASSERT_LE(std::atan2(w.y, w.x), kPi / 4 + 1e-12);
            dirs.push_back(toOctant(w, static_cast<int>(rng.uniform() * 8)));
        }
        test::ChiSquareOptions o;
        o.concentration = n;
        o.alpha = test::sidakAlpha(static_cast<int>(ns.size()));
        const auto r = test::chiSquareSphere(
            dirs, [n](const Vec3& w) { return phongLobePdf(w.z, n); }, o);
        EXPECT_TRUE(r.passed) << "n " << n << ": " << r.describe();
    }
}

// The mixture density that symmetric-mix reports integrates to one over the sphere (what its directions
// cover, the part below the surface included), for every material class.
TEST(SymmetricMixMaps, MixtureDensityIntegratesToOne) {
    for (const PhongMaterial& m : {material(0.7, 0, 1), material(0, 0.8, 50), material(0.2, 0.7, 100), material(0.3, 0.6, 0)})
        for (double deg : {0.0, 60.0}) {
            const ShadingContext ctx{sphericalDirection(std::cos(deg * kPi / 180), 0.3), &m, 0, false};
            test::ChiSquareOptions o;
            o.axis = Vec3(-ctx.wo.x, -ctx.wo.y, ctx.wo.z);
            o.concentration = m.exponent;
            const double total =
                test::integrateSphereAdaptive([&](const Vec3& w) { return SymmetricMixEstimator::directionDensity(ctx, w); }, o);
            EXPECT_NEAR(total, 1.0, 2e-3) << "kd " << m.rhoD.x << " ks " << m.rhoS.x << " n " << m.exponent << " theta " << deg;
        }
}

// ---------------------------------------------------------------------------------------------------
// Directions against the reported density

namespace {

struct MaterialClass {
    const char* name;
    double kd, ks;
};
const MaterialClass kClasses[] = {{"diffuse only", 0.7, 0.0}, {"glossy only", 0.0, 0.8}, {"mixed", 0.2, 0.7}};

}  // namespace

// Every copy of an orbit, at every orbit size, follows the mixture density q over the whole sphere: one
// copy per orbit (copy index k mod R), orbits independent. Then each direction the estimator returns,
// whatever its mode, has density q (the weights f cos / (R q) of tests/test_estimators.cpp rest on it).
TEST(SymmetricMixDensity, EveryCopyFollowsTheMixtureForEveryMaterialClass) {
    // Every n at the full orbit of 8; orbits 1 and 2 at n = 100 (the orbit changes which copies are
    // taken together, not the maps).
    struct Run {
        MaterialClass c;
        double n;
        int orbit;
    };
    std::vector<Run> runs;
    for (const auto& c : kClasses) {
        for (double n : {0.0, 1.0, 10.0, 100.0, 1000.0, 10000.0})
            if (c.ks > 0 || n == 0.0) runs.push_back({c, n, 8});
        for (int orbit : {1, 2}) runs.push_back({c, 100.0, orbit});
    }
    std::uint64_t seed = 900;
    for (const Run& run : runs) {
        const PhongMaterial m = material(run.c.kd, run.c.ks, run.n);
        const Vec3 wo = sphericalDirection(std::cos(50 * kPi / 180), 1.1);
        const ShadingContext ctx{wo, &m, 0, true};
        Rng rng(++seed, 9);
        std::vector<Vec3> dirs;
        for (int k = 0; k < 100000; ++k) {
            const auto o = SymmetricMixEstimator::makeOrbit(rng.uniform2(), rng.uniform(), run.orbit);
            dirs.push_back(SymmetricMixEstimator::copy(m, wo, o, k % run.orbit, run.orbit));
        }
        test::ChiSquareOptions opts;
        opts.alpha = test::sidakAlpha(static_cast<int>(runs.size()));
        if (run.c.ks > 0) {
            opts.axis = Vec3(-wo.x, -wo.y, wo.z);
            opts.concentration = run.n;
        }
        const auto r = test::chiSquareSphere(
            dirs, [&](const Vec3& w) { return SymmetricMixEstimator::directionDensity(ctx, w); }, opts);
        EXPECT_TRUE(r.passed) << run.c.name << " n " << run.n << " orbit " << run.orbit << ": " << r.describe();
    }
}

// Through the estimator interface at the first hit in spread mode: each camera sample (its own pixel, so
// samples are independent) returns copy pi(i mod R) of its round's orbit; the directions it keeps follow
// misPdf on the upper hemisphere and the share it drops (lobe directions below the surface) is misPdf's
// mass below it, within 4 binomial standard errors.
TEST(SymmetricMixDensity, SpreadModeFirstHitFollowsItsMisPdf) {
    std::uint64_t seed = 40;
    const std::vector<double> thetas = {0, 45, 80};
    const int runs = static_cast<int>(std::size(kClasses) * thetas.size());
    for (const auto& c : kClasses)
        for (double deg : thetas) {
            const PhongMaterial m = material(c.kd, c.ks, 20);
            EstimatorOptions o;
            o.symmetricMode = SymmetricMode::Spread;
            o.symmetricOrbit = 8;
            const auto est = makeEstimator("symmetric-mix", o);
            const ShadingContext ctx{sphericalDirection(std::cos(deg * kPi / 180), 0.4), &m, 0, true};
            test::Streams streams(++seed, "sobol", 64);
            std::vector<Vec3> dirs;
            DirectionList out;
            constexpr int kDraws = 100000;
            for (int k = 0; k < kDraws; ++k) {
                out.clear();
                streams.nextPixel();
                SampleStream s = streams.at(static_cast<std::uint32_t>(k % 64));
                est->sample(ctx, s, out);
                ASSERT_LE(out.size(), 1u);
                for (const auto& d : out) dirs.push_back(d.wi);
            }
            test::ChiSquareOptions opts;
            opts.alpha = test::sidakAlpha(runs);
            const auto upper = [&](const Vec3& w) { return w.z > 0 ? est->misPdf(ctx, w) : 0.0; };
            const double mass = test::integrateSphereAdaptive(upper, opts);
            const double omitted = 1.0 - static_cast<double>(dirs.size()) / kDraws;
            EXPECT_NEAR(omitted, 1.0 - mass, 4 * std::sqrt(std::max(mass * (1 - mass), 1.0 / kDraws) / kDraws))
                << c.name << " theta " << deg;
            const auto r = test::chiSquareSphere(
                dirs, [&](const Vec3& w) { return upper(w) / mass; }, opts);
            EXPECT_TRUE(r.passed) << c.name << " theta " << deg << ": " << r.describe();
        }
}

// An orbit's copies split between the families in proportion to P_d (stratified): of R copies,
// floor(R P_d) or ceil(R P_d) are diffuse, whatever the orbit's offset t.
TEST(SymmetricMixDensity, AnOrbitSplitsBetweenTheFamiliesInProportion) {
    const PhongMaterial m = material(0.2, 0.7, 1e6);  // a lobe so narrow that its copies are all within 1e-3 of the mirror direction
    const Vec3 wo = sphericalDirection(std::cos(0.5), 0.2), mirror(-wo.x, -wo.y, wo.z);
    const double pd = PhongLobeEstimator::diffuseProbability(m);
    Rng rng(3, 3);
    for (int orbit : {2, 4, 8})
        for (int k = 0; k < 2000; ++k) {
            const auto o = SymmetricMixEstimator::makeOrbit(rng.uniform2(), rng.uniform(), orbit);
            SymmetricMixEstimator::OrbitCopies copies(m, wo, o, orbit);
            int diffuse = 0;
            for (int j = 0; j < orbit; ++j) diffuse += dot(copies(j), mirror) < 1 - 1e-3 ? 1 : 0;
            EXPECT_GE(diffuse, static_cast<int>(std::floor(orbit * pd)));
            EXPECT_LE(diffuse, static_cast<int>(std::ceil(orbit * pd)));
        }
}

// The copies of one family are the signed permutations of one canonical point: for a diffuse material
// the R copies of an orbit have the same cos(theta) and lie in R different octants.
TEST(SymmetricMixDensity, CopiesAreTheSymmetricTwinsOfOnePoint) {
    const PhongMaterial m = material(0.8, 0, 1);
    Rng rng(8, 8);
    for (int orbit : {2, 4, 8})
        for (int k = 0; k < 500; ++k) {
            const auto o = SymmetricMixEstimator::makeOrbit(rng.uniform2(), rng.uniform(), orbit);
            SymmetricMixEstimator::OrbitCopies copies(m, Vec3(0, 0, 1), o, orbit);
            std::vector<int> octants;
            const Vec3 first = copies(0);
            for (int j = 0; j < orbit; ++j) {
                const Vec3 w = copies(j);
                EXPECT_NEAR(w.z, first.z, 1e-15);
                octants.push_back(octantOf(w));
            }
            std::sort(octants.begin(), octants.end());
            EXPECT_EQ(std::unique(octants.begin(), octants.end()), octants.end()) << "orbit " << orbit;
            if (orbit >= 2) {  // copies 0 and 1 are antipodal about the normal
                const Vec3 a = copies(0), b = copies(1);
                EXPECT_NEAR(a.x, -b.x, 1e-15);
                EXPECT_NEAR(a.y, -b.y, 1e-15);
            }
        }
}

// ---------------------------------------------------------------------------------------------------
// Unbiased on the furnace grid, both modes

namespace {

/// |t| of 16 independent furnace runs' mean against the exact value (error bar from their spread).
double furnaceT(const FurnaceSetup& base, const Environment& env, double& exact) {
    constexpr int kRuns = 16;
    std::vector<double> estimates;
    FurnaceSetup s = base;
    for (int run = 0; run < kRuns; ++run) {
        s.seed = mixSeed(base.seed, static_cast<std::uint64_t>(run));
        const FurnaceResult r = runFurnace(s, env);
        estimates.push_back(r.estimate);
        s.knownExact = exact = r.exact;
    }
    const auto m = test::meanAndError(estimates);
    return m.stdError > 0 ? std::abs(m.mean - exact) / m.stdError : (std::abs(m.mean - exact) < 1e-12 * std::abs(exact) ? 0.0 : INFINITY);
}

struct ModeOrbit {
    SymmetricMode mode;
    int orbit;
};

class SymmetricMixUnbiased : public ::testing::TestWithParam<ModeOrbit> {};

}  // namespace

// The furnace grid (n in 1..10^4, theta 0..85) under constant light, and every environment at two
// exponents and view angles; each cell's |t| below the 4-sigma tail of Student's t (15 dof).
TEST_P(SymmetricMixUnbiased, OnTheFurnaceGridAndEveryEnvironment) {
    FurnaceSetup s;
    s.estimator = "symmetric-mix";
    s.options.symmetricMode = GetParam().mode;
    s.options.symmetricOrbit = GetParam().orbit;
    s.rhoD = 0.3, s.rhoS = 0.6, s.phiDeg = 17, s.repeats = 300;
    s.sampler = "sobol";
    std::uint64_t cell = 0;
    const auto check = [&](const std::string& envName, double n, double theta) {
        s.n = n, s.thetaDeg = theta, s.seed = mixSeed(77, ++cell), s.knownExact = NAN;
        double exact = 0;
        const double t = furnaceT(s, makeEnvironment(envName), exact);
        EXPECT_LT(t, studentCritical(15)) << envName << " n " << n << " theta " << theta << " (exact " << exact << ")";
    };
    for (double n : furnaceGridExponents())
        for (double theta : furnaceGridThetas()) check("constant", n, theta);
    for (const std::string& env : environmentNames())
        for (double n : {1.0, 100.0})
            for (double theta : {10.0, 60.0}) check(env, n, theta);
}

INSTANTIATE_TEST_SUITE_P(Modes, SymmetricMixUnbiased,
                         ::testing::Values(ModeOrbit{SymmetricMode::Branch, 2}, ModeOrbit{SymmetricMode::Branch, 8},
                                           ModeOrbit{SymmetricMode::Spread, 2}, ModeOrbit{SymmetricMode::Spread, 8}),
                         [](const auto& info) {
                             return fmt::format("{}{}", info.param.mode == SymmetricMode::Spread ? "spread" : "branch", info.param.orbit);
                         });

// The white furnace at one point: constant radiance, purely diffuse material. Cosine sampling weighs every
// direction rho_d (zero variance); symmetric-mix's diffuse family is cosine sampling by pieces, so its
// variance per estimate is zero too (bound: at most cosine's), in both modes and at every orbit; the old
// `symmetric` in spread mode is not (its pieces are drawn 1/16 each).
TEST(SymmetricMixDiffuse, ConstantRadianceGivesZeroVarianceLikeCosine) {
    FurnaceSetup s;
    s.rhoD = 0.7, s.rhoS = 0.0, s.repeats = 200, s.thetaDeg = 40;
    s.estimator = "cosine";
    const FurnaceResult cosine = runFurnace(s, makeEnvironment("constant"));
    EXPECT_LT(cosine.variance, 1e-24);
    s.estimator = "symmetric-mix";
    for (SymmetricMode mode : {SymmetricMode::Branch, SymmetricMode::Spread})
        for (int orbit : {1, 2, 4, 8}) {
            s.options.symmetricMode = mode;
            s.options.symmetricOrbit = orbit;
            const FurnaceResult r = runFurnace(s, makeEnvironment("constant"));
            EXPECT_NEAR(r.estimate, 0.7, 1e-12) << symmetricModeName(mode) << " " << orbit;
            EXPECT_LE(r.variance, cosine.variance + 1e-24) << symmetricModeName(mode) << " " << orbit;
        }
    // One direction per call (deeper bounces): symmetric-mix weighs every direction rho_d; the old
    // `symmetric` weighs a piece's direction 16 Phi_piece / pi rho_d, 1.108 rho_d or 0.892 rho_d.
    const PhongMaterial m = material(0.7, 0, 1);
    const ShadingContext ctx{sphericalDirection(std::cos(0.7), 0.1), &m, 1, false};
    test::Streams streams(5);
    DirectionList out;
    for (const char* name : {"symmetric-mix", "symmetric"}) {
        const auto est = makeEstimator(name);
        double lo = INFINITY, hi = -INFINITY;
        for (int k = 0; k < 4000; ++k) {
            out.clear();
            SampleStream samples = streams.next();
            est->sample(ctx, samples, out);
            for (const auto& d : out) lo = std::min(lo, d.weight.x), hi = std::max(hi, d.weight.x);
        }
        if (std::string(name) == "symmetric-mix") {
            EXPECT_NEAR(lo, 0.7, 1e-12);
            EXPECT_NEAR(hi, 0.7, 1e-12);
        } else {
            EXPECT_NEAR(hi, 0.7 * 16 * kTriangleProjected / kPi, 1e-9) << "cause 1, triangles";
            EXPECT_NEAR(lo, 0.7 * 16 * kQuadrangleProjected / kPi, 1e-9) << "cause 1, quadrangles";
        }
    }
}
