// Environment maps (scene/environment_map.h, sampling/distribution2d.h, their light sampling in
// render/path_tracer): the sampler's density integrates to 1 over the sphere and its directions pass a
// chi-square test against it; a map of constant value renders the same image as the constant
// environment with every estimator (light sampling + MIS against each); a map black but for one texel
// lights a plane with the irradiance of that texel's solid angle; a rotated map is seen and sampled where
// the documented formula puts each texel, in proportion to its luminance; JSON errors; radiance and density
// looked up together are each looked up alone.
#include "stats.h"
#include "test_util.h"

#include "compare/metrics.h"
#include "io/image.h"
#include "io/input_error.h"
#include "sampling/warp.h"
#include "scene/environment_map.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <utility>

using namespace symphong;
using symphong::test::integrateOverSphere;

namespace {

Texture constantImage(int w, int h, double value) {
    return Texture("constant", w, h, 3, std::vector<float>(static_cast<std::size_t>(w * h * 3), static_cast<float>(value)));
}

/// A map with smoothly varying, strictly positive texels and one bright one.
Texture variedImage(int w, int h) {
    std::vector<float> t(static_cast<std::size_t>(w * h * 3));
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < 3; ++c)
                t[static_cast<std::size_t>((y * w + x) * 3 + c)] =
                    static_cast<float>(0.2 + 0.15 * std::sin(0.7 * x + c) + 0.1 * y + (x == 3 && y == 2 ? 20 : 0));
    return Texture("varied", w, h, 3, std::move(t));
}

/// A floor (glossy) with a block standing on it, seen from above at an angle.
Scene floorWithBlock() {
    Scene s;
    PhongMaterial floor;
    floor.name = "floor";
    floor.rhoD = Color(0.5);
    floor.rhoS = Color(0.3);
    floor.exponent = 20;
    PhongMaterial block;
    block.name = "block";
    block.rhoD = Color(0.7, 0.5, 0.3);
    s.materials = {floor, block};
    test::addQuad(s, {-2, 0, 2}, {2, 0, 2}, {2, 0, -2}, {-2, 0, -2}, 0);
    const double h = 0.8;
    test::addQuad(s, {-0.5, h, 0.5}, {0.5, h, 0.5}, {0.5, h, -0.5}, {-0.5, h, -0.5}, 1);    // top
    test::addQuad(s, {-0.5, 0, 0.5}, {0.5, 0, 0.5}, {0.5, h, 0.5}, {-0.5, h, 0.5}, 1);      // front
    test::addQuad(s, {0.5, 0, 0.5}, {0.5, 0, -0.5}, {0.5, h, -0.5}, {0.5, h, 0.5}, 1);      // right
    test::addQuad(s, {-0.5, 0, -0.5}, {-0.5, 0, 0.5}, {-0.5, h, 0.5}, {-0.5, h, -0.5}, 1);  // left
    s.camera.position = Vec3(1.5, 2.5, 3.5);
    s.camera.target = Vec3(0, 0.2, 0);
    s.camera.fovY = 45;
    return s;
}

}  // namespace

// The lookup a path that leaves the scene makes (radiance and density from one mapping of its direction)
// gives radiance() and pdf() bit for bit, with either filter, rotated or not, and a black map's density 0.
TEST(EnvironmentMap, RadianceAndPdfTogetherAreEachAlone) {
    Rng rng(7, 3);
    for (const auto filter : {EnvironmentMap::Filter::Nearest, EnvironmentMap::Filter::Bilinear})
        for (const double rotation : {0.0, 37.0}) {
            const EnvironmentMap env(variedImage(16, 8), 1.5, rotation, filter);
            const EnvironmentMap black(constantImage(4, 2, 0.0), 1.0, rotation, filter);
            for (int i = 0; i < 2000; ++i) {
                const Vec3 d = sphericalDirection(2 * rng.uniform() - 1, kTwoPi * rng.uniform());
                double pdf = -1, blackPdf = -1;
                const Color L = env.radianceAndPdf(d, pdf);
                const Color alone = env.radiance(d);
                EXPECT_TRUE(L.x == alone.x && L.y == alone.y && L.z == alone.z);
                EXPECT_EQ(pdf, env.pdf(d));
                black.radianceAndPdf(d, blackPdf);
                EXPECT_EQ(blackPdf, 0.0);
            }
        }
}

TEST(EnvironmentMap, MappingRoundTripsAndPutsTheImageCentreAtMinusZ) {
    const EnvironmentMap env(variedImage(16, 8), 1.0, 30.0, EnvironmentMap::Filter::Nearest);
    Rng rng(1, 2);
    for (int i = 0; i < 1000; ++i) {
        const double u = rng.uniform(), t = 0.01 + 0.98 * rng.uniform();
        double u2, t2;
        env.toImage(env.fromImage(u, t), u2, t2);
        EXPECT_NEAR(u, u2, 1e-9);
        EXPECT_NEAR(t, t2, 1e-9);
    }
    const EnvironmentMap plain(variedImage(16, 8), 1.0, 0.0, EnvironmentMap::Filter::Nearest);
    const Vec3 centre = plain.fromImage(0.5, 0.5);
    EXPECT_NEAR(centre.z, -1.0, 1e-12);
    EXPECT_NEAR(plain.fromImage(0.3, 0.0).y, 1.0, 1e-12);  // the top row is the zenith
}

TEST(EnvironmentMap, SamplerDensityIntegratesToOneAndMatchesItsDirections) {
    for (const auto filter : {EnvironmentMap::Filter::Nearest, EnvironmentMap::Filter::Bilinear}) {
        const EnvironmentMap env(variedImage(16, 8), 1.0, 10.0, filter);
        const auto pdf = [&](const Vec3& d) { return env.pdf(d); };
        EXPECT_NEAR(integrateOverSphere(pdf, 1600, 640), 1.0, 2e-3);
        Rng rng(7, 1);
        std::vector<Vec3> dirs;
        for (int i = 0; i < 200000; ++i) {
            double p;
            const Vec3 d = env.sample(rng.uniform2(), p);
            ASSERT_GT(p, 0);
            ASSERT_NEAR(p, env.pdf(d), 1e-6 * p) << "sample() and pdf() disagree";
            dirs.push_back(d);
        }
        // Chi-square over the image's texels, each split in 2 x 2 (the density is constant over a texel
        // in image coordinates, where a sub-cell's share is a quarter of its texel's). The texels' own
        // probabilities come from integrating pdf(w) over their solid angle, not from the sampler's table.
        const int w = env.image().width(), h = env.image().height();
        std::vector<double> observed(static_cast<std::size_t>(4 * w * h), 0.0), expected(observed.size(), 0.0);
        for (const Vec3& d : dirs) {
            double u, t;
            env.toImage(d, u, t);
            const int sx = std::min(2 * w - 1, static_cast<int>(u * 2 * w)), sy = std::min(2 * h - 1, static_cast<int>(t * 2 * h));
            observed[static_cast<std::size_t>(sy * 2 * w + sx)] += 1;
        }
        double total = 0;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const Vec3 centre = env.fromImage((x + 0.5) / w, (y + 0.5) / h);
                const double p = env.pdf(centre) * std::sin(kPi * (y + 0.5) / h) * (2 * kPi * kPi) / (w * h);  // image-space probability
                total += p;
                for (int k = 0; k < 4; ++k)
                    expected[static_cast<std::size_t>((2 * y + k / 2) * 2 * w + 2 * x + k % 2)] = p / 4 * static_cast<double>(dirs.size());
            }
        EXPECT_NEAR(total, 1.0, 1e-9);
        const auto r = test::chiSquareCounts(observed, expected, test::sidakAlpha(2));
        EXPECT_TRUE(r.passed) << filterName(filter) << ": " << r.describe();
    }
}

// Rotation and density against the map itself. Directions are put into texels by the documented mapping
// written out here (u = 1/2 + atan2(x, -z) / 2 pi - rotation / 360, t = theta / pi; docs/scene-format.md),
// never through toImage/fromImage, so a rotation turned the wrong way in both stays visible. Each texel's
// share of the samples must be its luminance x sin(theta at its centre) over the sum of those (the density
// the header promises: proportional to Y over the sphere up to sin(theta_c)/sin(theta) inside a texel).
TEST(EnvironmentMap, RotatedMapIsSeenAndSampledWhereTheFormulaPutsItsTexels) {
    const int w = 16, h = 8;
    const Texture img = variedImage(w, h);
    for (const double rotation : {0.0, 90.0, -37.5}) {
        const EnvironmentMap env(img, 1.0, rotation, EnvironmentMap::Filter::Nearest);
        const auto direction = [&](double u, double t) {
            const double phi = kTwoPi * (u - 0.5 + rotation / 360.0), theta = kPi * t;
            return Vec3(std::sin(theta) * std::sin(phi), std::cos(theta), -std::sin(theta) * std::cos(phi));
        };
        const auto texelOf = [&](const Vec3& d) {
            double u = 0.5 + std::atan2(d.x, -d.z) / kTwoPi - rotation / 360.0;
            u -= std::floor(u);
            const double t = std::acos(std::clamp(d.y, -1.0, 1.0)) / kPi;
            return std::pair{std::min(w - 1, static_cast<int>(u * w)), std::min(h - 1, static_cast<int>(t * h))};
        };
        std::vector<double> share(static_cast<std::size_t>(w * h));
        double total = 0;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const Color texel = img.texelRgb(x, y);
                const Color seen = env.radiance(direction((x + 0.5) / w, (y + 0.5) / h));
                ASSERT_NEAR(seen.x, texel.x, 1e-6) << "rotation " << rotation << ", texel " << x << ", " << y;
                ASSERT_NEAR(seen.z, texel.z, 1e-6) << "rotation " << rotation << ", texel " << x << ", " << y;
                share[static_cast<std::size_t>(y * w + x)] = luminance(texel) * std::sin(kPi * (y + 0.5) / h);
                total += share[static_cast<std::size_t>(y * w + x)];
            }
        for (double& s : share) s /= total;
        Rng rng(17, static_cast<std::uint64_t>(rotation + 100));
        const int n = 200000;
        std::vector<double> observed(share.size(), 0.0), expected(share.size());
        for (int i = 0; i < n; ++i) {
            double p;
            const Vec3 d = env.sample(rng.uniform2(), p);
            const auto [x, y] = texelOf(d);
            observed[static_cast<std::size_t>(y * w + x)] += 1;
            // The solid-angle density from the texel's share: share x W H / (2 pi^2 sin theta).
            const double sinTheta = std::sqrt(std::max(0.0, 1 - d.y * d.y));
            const double fromShare = share[static_cast<std::size_t>(y * w + x)] * w * h / (2 * kPi * kPi * sinTheta);
            ASSERT_NEAR(env.pdf(d), fromShare, 1e-6 * fromShare) << "rotation " << rotation << ", texel " << x << ", " << y;
        }
        for (std::size_t k = 0; k < share.size(); ++k) expected[k] = share[k] * n;
        const auto r = test::chiSquareCounts(observed, expected, test::sidakAlpha(3));
        EXPECT_TRUE(r.passed) << "rotation " << rotation << ": " << r.describe();
    }
}

TEST(EnvironmentMap, LuminanceIntegralOfAConstantMapIsFourPiL) {
    const EnvironmentMap env(constantImage(8, 4, 0.5), 2.0, 0.0, EnvironmentMap::Filter::Bilinear);
    EXPECT_NEAR(env.luminanceIntegral(), 4 * kPi * 1.0, 1e-9);
    EXPECT_NEAR(env.radiance(normalize(Vec3(0.3, -0.4, 0.2))).y, 1.0, 1e-12);
}

// The same scene under a constant environment L (only reached by the estimators' paths) and under a
// lat-long map of value L (light-sampled and combined by MIS with each estimator): the same image mean.
TEST(EnvironmentMap, ConstantMapRendersAsTheConstantEnvironmentWithEveryEstimator) {
    Scene constant = floorWithBlock();
    constant.environment = Color(0.7);
    Scene mapped = floorWithBlock();
    mapped.environmentMap.emplace(constantImage(8, 4, 0.7), 1.0, 0.0, EnvironmentMap::Filter::Bilinear);
    for (const std::string estimator : {"uniform", "cosine", "phong", "symmetric", "symmetric-shifted"}) {
        const auto [a, sa] = test::imageMeanAndError(test::renderIndependent(constant, estimator, 24, 16, 11));
        const auto [b, sb] = test::imageMeanAndError(test::renderIndependent(mapped, estimator, 24, 16, 12));
        EXPECT_NEAR(a, b, 4 * std::hypot(sa, sb)) << estimator << ": se " << sa << ", " << sb;
        EXPECT_GT(a, 0.1) << estimator;
    }
    // The paper's estimator has no density, so the map is not light-sampled: still the same light.
    const auto [a, sa] = test::imageMeanAndError(test::renderIndependent(constant, "cosine", 24, 16, 13, false));
    const auto [b, sb] = test::imageMeanAndError(test::renderIndependent(mapped, "cosine", 24, 16, 14, false));
    EXPECT_NEAR(a, b, 4 * std::hypot(sa, sb)) << "without light sampling";
}

// The white furnace: a convex diffuse sphere of albedo 1 under a constant environment L sends back L
// from every point, so it vanishes against the background. Under a constant *map* (light-sampled and
// MIS-combined) it must vanish as well, with every estimator; so must a sphere of albedo 0.5 at L/2.
TEST(EnvironmentMap, WhiteFurnaceSphereUnderAConstantMapVanishes) {
    for (const double albedo : {1.0, 0.5}) {
        Scene s;
        PhongMaterial m;
        m.rhoD = Color(albedo);
        s.materials = {m};
        test::addUvSphere(s, 0, true, 24, 48);
        s.camera.position = Vec3(0, 0.5, 3);
        s.camera.target = Vec3(0, 0, 0);
        s.camera.fovY = 30;  // the sphere fills most of the view, every pixel sees it
        s.environmentMap.emplace(constantImage(16, 8, 0.8), 1.0, 25.0, EnvironmentMap::Filter::Bilinear);
        for (const std::string estimator : {"cosine", "phong", "symmetric"}) {
            const RenderResult r = test::renderIndependent(s, estimator, 16, 16, 31);
            if (albedo == 1.0) {
                // Background pixels see L, sphere pixels albedo x L = L: the whole image is L.
                const auto [mean, se] = test::imageMeanAndError(r);
                EXPECT_NEAR(mean, 0.8, 4 * se) << estimator << ": se " << se;
            }
            // The central 8 x 8 pixels see only the sphere: albedo x L there.
            double sum = 0, var = 0;
            for (int y = 4; y < 12; ++y)
                for (int x = 4; x < 12; ++x) sum += luminance(r.image.at(x, y)), var += luminanceVariance(r.variance.at(x, y));
            EXPECT_NEAR(sum / 64, albedo * 0.8, 4 * std::sqrt(var) / 64) << estimator << ", albedo " << albedo;
        }
    }
}

// One texel of radiance Lp at row y, everything else black; nearest filtering. A diffuse plane facing
// up receives E = Lp dphi integral_{theta0}^{theta1} cos(theta) sin(theta) dtheta
//              = Lp (2 pi / W) (sin^2 theta1 - sin^2 theta0) / 2,
// and sends back rho_d E / pi everywhere.
TEST(EnvironmentMap, OneBrightTexelLightsAPlaneWithItsSolidAngle) {
    const int w = 16, h = 8, bx = 5, by = 2;
    const double lp = 50, rho = 0.6;
    std::vector<float> t(static_cast<std::size_t>(w * h * 3), 0.0f);
    for (int c = 0; c < 3; ++c) t[static_cast<std::size_t>((by * w + bx) * 3 + c)] = static_cast<float>(lp);
    Scene s;
    PhongMaterial m;
    m.rhoD = Color(rho);
    s.materials = {m};
    test::addQuad(s, {-1, 0, 1}, {1, 0, 1}, {1, 0, -1}, {-1, 0, -1}, 0);
    s.camera.position = Vec3(0, 3, 0.001);
    s.camera.target = Vec3(0, 0, 0);
    s.camera.fovY = 30;
    s.environmentMap.emplace(Texture("one", w, h, 3, std::move(t)), 1.0, 0.0, EnvironmentMap::Filter::Nearest);
    const double th0 = kPi * by / h, th1 = kPi * (by + 1) / h;
    const double e = lp * (kTwoPi / w) * 0.5 * (std::pow(std::sin(th1), 2) - std::pow(std::sin(th0), 2));
    const double expected = rho * e / kPi;
    for (const std::string estimator : {"cosine", "phong"}) {
        const auto [mean, se] = test::imageMeanAndError(test::renderIndependent(s, estimator, 16, 64, 21));
        EXPECT_NEAR(mean, expected, 4 * se + 1e-9) << estimator << ": se " << se;
        EXPECT_LT(se, 0.02 * expected) << estimator << ": the map's light sampling should find the texel";
    }
}

TEST(EnvironmentMap, JsonScenesNameTheMapAndItsErrors) {
    test::TempDir dir;
    Image img(8, 4);
    for (auto& p : img.pixels) p = Color(0.5);
    writeExr(img, dir.file("sky.exr"));
    const std::string scene = std::string(SYMPHONG_SOURCE_DIR) + "/scenes/cornell-classic.obj";
    const auto json = [&](const std::string& env) {
        return dir.write("s.json", "{\"mesh\": \"" + scene + "\", \"environment\": " + env + "}");
    };
    const Scene s = loadScene(json(R"({"map": ")" + dir.file("sky.exr") + R"(", "scale": 2, "rotation": 90, "filter": "nearest"})"));
    ASSERT_TRUE(s.environmentMap.has_value());
    EXPECT_DOUBLE_EQ(s.environmentMap->scale(), 2.0);
    EXPECT_EQ(s.environmentMap->filter(), EnvironmentMap::Filter::Nearest);
    EXPECT_FALSE(s.sky.has_value());  // a map is light: no default sky
    EXPECT_NEAR(s.environmentRadiance(Vec3(0, 1, 0)).x, 1.0, 1e-6);
    const auto expectError = [&](const std::string& env, const std::string& needle) {
        try {
            loadScene(json(env));
            ADD_FAILURE() << env << " was accepted";
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
        }
    };
    expectError(R"({"map": "absent.hdr"})", "absent.hdr: no such file");
    expectError(R"({"map": ")" + dir.file("sky.exr") + R"(", "filter": "cubic"})", "environment.filter");
    expectError(R"({"map": ")" + dir.file("sky.exr") + R"(", "scale": -1})", "environment.scale");
    expectError(R"({"map": ")" + dir.file("sky.exr") + R"(", "blur": 1})", "unknown key 'blur'");
    expectError(R"({"scale": 1})", "environment.map");
    Image neg(2, 1);
    neg.at(1, 0) = Color(0, -1, 0);
    writeExr(neg, dir.file("neg.exr"));
    expectError(R"({"map": ")" + dir.file("neg.exr") + R"("})", "neg.exr: texel (1, 0) channel 1 is -1");
}
