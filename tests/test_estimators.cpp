// Furnace tests of every estimator at a single shading point: under a constant incoming radiance
// L = 1 the reflected radiance is the directional albedo, known exactly (materials/phong.h). Each
// estimator's mean must match it within 4 standard errors, for diffuse and glossy Phong materials
// and view angles up to 85 degrees. Also: the weights and MIS densities estimators report agree.
#include "estimators/estimator.h"
#include "sample_util.h"
#include "sampling/warp.h"
#include "stats.h"

#include <gtest/gtest.h>

#include <fmt/format.h>

#include <algorithm>
#include <tuple>

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

/// An estimator in a mode, under a sampler.
struct Config {
    std::string estimator, sampler;
    SymmetricMode mode = SymmetricMode::Branch;
    std::string label() const {
        std::string n = estimator + "_" + sampler + (mode == SymmetricMode::Spread ? "_spread" : "");
        std::replace(n.begin(), n.end(), '-', '_');
        return n;
    }
};

/// Every estimator but `paper` (biased on purpose) under every sampler; the set estimators in both modes.
std::vector<Config> unbiasedConfigs() {
    std::vector<Config> configs;
    for (const auto& e : estimatorNames()) {
        if (e == "paper") continue;
        for (const auto& s : samplerNames()) {
            if (e == "stratified" && s != "stratified") continue;  // bound to its own sampler
            configs.push_back({e, s});
            if (hasSymmetricModes(e)) configs.push_back({e, s, SymmetricMode::Spread});  // paper skipped above
        }
    }
    return configs;
}

/// How GoogleTest prints a Config (instead of its bytes).
[[maybe_unused]] void PrintTo(const Config& c, std::ostream* os) { *os << c.label(); }

class EstimatorFurnace : public ::testing::TestWithParam<Config> {};

}  // namespace

// One estimate = the mean of a group of 16 calls: the 16 camera samples of one pixel of the sampler
// (so stratified and sobol stratify them, and spread mode spreads its set over them); groups are
// different pixels, independent, so their spread gives the standard error. Half the groups are first
// hits (set estimators return their whole set, or spread it), half deeper bounces (one direction).
TEST_P(EstimatorFurnace, MatchesTheDirectionalAlbedo) {
    const Config& c = GetParam();
    EstimatorOptions options;
    options.symmetricMode = c.mode;
    const auto estimator = makeEstimator(c.estimator, options);
    constexpr std::uint32_t kGroup = 16;
    test::Streams streams(1234, c.sampler, kGroup);
    DirectionList out;
    // Estimators that return a whole set of directions per call need fewer calls for the same precision.
    const int kGroups = estimator->returnsSets() ? 2000 : 6000;
    for (const FurnaceCase& fc : furnaceCases()) {
        PhongMaterial m;
        m.rhoD = Color(fc.kd);
        m.rhoS = Color(fc.ks);
        m.exponent = fc.n;
        const Vec3 wo = sphericalDirection(std::cos(fc.thetaDeg * kPi / 180), 0.7);
        const double exact = phongDirectionalAlbedo(m, wo).x;
        for (bool branch : {true, false}) {
            std::vector<double> groups(kGroups / 2);
            for (double& g : groups) {
                streams.nextPixel();
                double sum = 0;
                for (std::uint32_t i = 0; i < kGroup; ++i) {
                    out.clear();
                    SampleStream samples = streams.at(i);
                    estimator->sample(ShadingContext{wo, &m, branch ? 0 : 1, branch}, samples, out);
                    for (const auto& s : out) sum += s.weight.x;
                }
                g = sum / kGroup;
            }
            const auto s = test::meanAndError(groups);
            const std::string what = fmt::format("{} (branch {}): kd {} ks {} n {} theta {} -> {} +- {} vs exact {}", c.label(), branch,
                                                 fc.kd, fc.ks, fc.n, fc.thetaDeg, s.mean, s.stdError, exact);
            EXPECT_NEAR(s.mean, exact, 4 * s.stdError + 1e-9 * exact) << what;
        }
    }
}

TEST_P(EstimatorFurnace, WeightsAreBrdfCosineOverTheReportedDensity) {
    const Config& c = GetParam();
    EstimatorOptions options;
    options.symmetricMode = c.mode;
    const auto estimator = makeEstimator(c.estimator, options);
    test::Streams streams(77, c.sampler, 8);
    Rng rng(77, 7);
    PhongMaterial m;
    m.rhoD = Color(0.3);
    m.rhoS = Color(0.5);
    m.exponent = 20;
    DirectionList out;
    for (bool branch : {false, true})
        for (int k = 0; k < 2000; ++k) {
            const Vec3 wo = sampleUniformHemisphere(rng.uniform2());
            const ShadingContext ctx{wo, &m, branch ? 0 : 1, branch};
            out.clear();
            streams.nextPixel();
            SampleStream samples = streams.at(static_cast<std::uint32_t>(k % 8));
            estimator->sample(ctx, samples, out);
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

INSTANTIATE_TEST_SUITE_P(EveryEstimatorAndSampler, EstimatorFurnace, ::testing::ValuesIn(unbiasedConfigs()),
                         [](const auto& info) { return info.param.label(); });

// At deeper bounces `paper` keeps one of its directions: the same expectation as the whole set.
TEST(PaperEstimator, OneDirectionHasTheSameMeanAsTheWholeSet) {
    const auto paper = makeEstimator("paper", EstimatorOptions{2, false});
    PhongMaterial m;
    m.rhoD = Color(0.5);
    m.rhoS = Color(0.4);
    m.exponent = 20;
    const Vec3 wo = sphericalDirection(std::cos(0.5), 0.3);
    test::Streams streams(31);
    DirectionList out;
    for (bool branch : {true, false}) {
        std::vector<double> v(branch ? 50000 : 2000000);
        for (double& x : v) {
            out.clear();
            SampleStream samples = streams.next();
            paper->sample(ShadingContext{wo, &m, branch ? 0 : 1, branch}, samples, out);
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

// Estimator::largestSet, by which the wavefront tracer sizes its batch (render/wavefront.cpp), against the sets
// that calls return: no call at a first hit returns more; a set estimator in branch mode returns that many at a
// glossy point seen from near its normal (every piece's direction above the surface), so the bound is not loose.
// The other estimators, and every estimator off the first hit, return at most one direction.
TEST(EstimatorSets, LargestSetIsTheMostDirectionsOneCallReturns) {
    PhongMaterial m;
    m.rhoD = Color(0.5);
    m.rhoS = Color(0.4);
    m.exponent = 200;
    test::Streams streams(77);
    DirectionList out;
    for (const auto& name : estimatorNames())
        for (int n : {1, 3})
            for (int orbit : {2, 8}) {
                EstimatorOptions options;
                options.symmetricN = n;
                options.symmetricOrbit = orbit;
                const auto est = makeEstimator(name, options);
                std::size_t most = 0, mostDeeper = 0;
                for (int call = 0; call < 200; ++call)
                    for (bool branch : {true, false}) {
                        out.clear();
                        SampleStream samples = streams.next();
                        est->sample(ShadingContext{sphericalDirection(std::cos(0.05), 0.3 * call), &m, branch ? 0 : 1, branch}, samples,
                                    out);
                        (branch ? most : mostDeeper) = std::max(branch ? most : mostDeeper, out.size());
                    }
                EXPECT_LE(mostDeeper, 1u) << name;
                if (est->returnsSets())
                    EXPECT_EQ(most, est->largestSet()) << name << " N' " << n << " orbit " << orbit;
                else
                    EXPECT_EQ(est->largestSet(), 1u) << name;
                EXPECT_LE(most, est->largestSet()) << name << " N' " << n << " orbit " << orbit;
            }
}

// Every estimator's one-direction density (the misPdf it reports for MIS, the symmetric estimators'
// mixture over their pieces included) against the directions it draws, by the chi-square helper
// (tests/stats.h): the directions it returns follow misPdf restricted to the upper hemisphere, and the
// fraction it omits (directions rotated below the surface) is the mass misPdf leaves out, within 4
// binomial standard errors. Independent streams, one per call; Sidak-corrected alpha over the runs.
TEST(EstimatorDensities, OneDirectionFollowsTheReportedMisPdf) {
    const std::vector<std::string> names = {"uniform", "cosine", "phong", "symmetric", "symmetric-shifted"};
    const std::vector<double> thetas = {0.0, 45.0, 80.0};
    const int runs = static_cast<int>(names.size() * thetas.size());
    constexpr int kDraws = 200000;
    PhongMaterial m;
    m.rhoD = Color(0.3);
    m.rhoS = Color(0.6);
    m.exponent = 20;
    std::uint64_t seed = 500;
    for (const std::string& name : names) {
        const auto est = makeEstimator(name);
        for (double deg : thetas) {
            const ShadingContext ctx{sphericalDirection(std::cos(deg * kPi / 180), 0.4), &m, 1, false};
            test::Streams streams(++seed);
            std::vector<Vec3> dirs;
            DirectionList out;
            for (int k = 0; k < kDraws; ++k) {
                out.clear();
                SampleStream samples = streams.next();
                est->sample(ctx, samples, out);
                for (const auto& s : out) dirs.push_back(s.wi);
            }
            test::ChiSquareOptions opts;
            opts.alpha = test::sidakAlpha(runs);
            const auto upper = [&](const Vec3& w) { return w.z > 0 ? est->misPdf(ctx, w) : 0.0; };
            const double mass = test::integrateSphereAdaptive(upper, opts);
            const double omitted = 1.0 - static_cast<double>(dirs.size()) / kDraws;
            EXPECT_NEAR(omitted, 1.0 - mass, 4 * std::sqrt(std::max(mass * (1 - mass), 1.0 / kDraws) / kDraws))
                << name << " theta " << deg << ": omitted " << omitted << ", misPdf's mass below the horizon " << 1 - mass;
            const auto r = test::chiSquareSphere(
                dirs, [&](const Vec3& w) { return upper(w) / mass; }, opts);
            EXPECT_TRUE(r.passed) << name << " theta " << deg << ": " << r.describe();
        }
    }
}

// Estimator::drawAhead + sampleDrawn (the wavefront tracer's directions drawn ahead of their vertices) against
// sample() from the stream whose first 2D value was drawn from: the same direction, weight and density, bit for
// bit, for diffuse, glossy and purely specular materials at view angles up to 85 degrees; a null material's
// slot is left as it was.
TEST(EstimatorDrawAhead, DrawnDirectionsAreTheSampledOnes) {
    std::vector<PhongMaterial> materials;
    for (const auto& [kd, ks, n] : std::vector<std::tuple<double, double, double>>{
             {0.8, 0.0, 1.0}, {0.2, 0.7, 1.0}, {0.2, 0.7, 10.0}, {0.3, 0.6, 100.0}, {0.05, 0.9, 1000.0}, {0.0, 0.9, 50.0}}) {
        PhongMaterial m;
        m.rhoD = Color(kd);
        m.rhoS = Color(ks);
        m.exponent = n;
        materials.push_back(m);
    }
    int drawing = 0;
    for (const auto& name : estimatorNames()) {
        const auto est = makeEstimator(name);
        if (!est->drawsAhead(false)) continue;
        ++drawing;
        test::Streams streams(77);
        constexpr std::size_t kPoints = 4000;
        std::vector<const PhongMaterial*> mats(kPoints);
        std::vector<double> us(kPoints), vs(kPoints);
        std::vector<ShadingContext> contexts(kPoints);
        std::vector<DirectionList> sampled(kPoints);
        for (std::size_t i = 0; i < kPoints; ++i) {
            mats[i] = i % 97 == 5 ? nullptr : &materials[i % materials.size()];
            const double deg = 85.0 * static_cast<double>(i % 13) / 12.0;
            contexts[i] = {sphericalDirection(std::cos(deg * kPi / 180), 0.3 + 0.1 * static_cast<double>(i % 7)),
                           &materials[i % materials.size()], static_cast<int>(i % 3), false};
            SampleStream samples = streams.next();
            SampleStream first = samples;
            const Point2 u = first.get2D();
            us[i] = u.u;
            vs[i] = u.v;
            est->sample(contexts[i], samples, sampled[i]);
        }
        const DirectionDraw untouched{Vec3(7.0, 8.0, 9.0), true};
        std::vector<DirectionDraw> draws(kPoints, untouched);
        est->drawAhead(mats.data(), us.data(), vs.data(), kPoints, draws.data());
        std::size_t compared = 0;
        for (std::size_t i = 0; i < kPoints; ++i) {
            if (!mats[i]) {
                EXPECT_TRUE(draws[i].local == untouched.local && draws[i].aroundMirror)
                    << name << " point " << i << ": a null material's slot written";
                continue;
            }
            DirectionList drawn;
            est->sampleDrawn(contexts[i], draws[i], drawn);
            ASSERT_EQ(drawn.size(), sampled[i].size()) << name << " point " << i;
            for (std::size_t j = 0; j < drawn.size(); ++j) {
                EXPECT_TRUE(drawn[j].wi == sampled[i][j].wi && drawn[j].weight == sampled[i][j].weight &&
                            drawn[j].misPdf == sampled[i][j].misPdf)
                    << name << " point " << i;
                ++compared;
            }
        }
        EXPECT_GT(compared, kPoints * 3 / 4) << name << ": most points give a direction above the surface";
    }
    EXPECT_GE(drawing, 2) << "phong and symmetric-mix draw ahead";
}

// symmetric-mix's deeper vertices (ctx.branch false) are phong's: from the same stream, the same direction,
// weight and density, bit for bit (phong, the second method, is tested on its own above and in the chi-square
// and furnace tests); at the first hit (ctx.branch true) it does not claim to draw ahead, and returns its orbit.
TEST(EstimatorDrawAhead, SymmetricMixDeeperVerticesArePhongs) {
    PhongMaterial m;
    m.rhoD = Color(0.3);
    m.rhoS = Color(0.6);
    m.exponent = 20;
    const auto phong = makeEstimator("phong");
    for (const int orbit : {2, 8}) {
        EstimatorOptions o;
        o.symmetricOrbit = orbit;
        const auto mix = makeEstimator("symmetric-mix", o);
        EXPECT_TRUE(mix->drawsAhead(false));
        EXPECT_FALSE(mix->drawsAhead(true));
        test::Streams streams(5);
        std::size_t compared = 0;
        for (int i = 0; i < 2000; ++i) {
            const double deg = 85.0 * static_cast<double>(i % 17) / 16.0;
            const ShadingContext deeper{sphericalDirection(std::cos(deg * kPi / 180), 0.2 * i), &m, 1 + i % 3, false};
            SampleStream a = streams.next();
            SampleStream b = a;
            DirectionList fromMix, fromPhong;
            mix->sample(deeper, a, fromMix);
            phong->sample(deeper, b, fromPhong);
            ASSERT_EQ(fromMix.size(), fromPhong.size()) << "point " << i;
            for (std::size_t j = 0; j < fromMix.size(); ++j, ++compared)
                EXPECT_TRUE(fromMix[j].wi == fromPhong[j].wi && fromMix[j].weight == fromPhong[j].weight &&
                            fromMix[j].misPdf == fromPhong[j].misPdf)
                    << "orbit " << orbit << " point " << i;
            ShadingContext first = deeper;
            first.depth = 0, first.branch = true;
            SampleStream c = streams.next();
            DirectionList set;
            mix->sample(first, c, set);
            EXPECT_LE(set.size(), static_cast<std::size_t>(orbit));
        }
        EXPECT_GT(compared, 1500u);
    }
}
