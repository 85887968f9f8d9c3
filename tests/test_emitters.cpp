// The emitters behind one interface (lights/): each kind against a closed form (a point light's I/d^2, a
// spot's falloff at several angles, a directional light's E), every area emitter's sample density against
// its density of a hit along the same direction (a second code path), the triangle's density against the
// triangle's solid angle (Van Oosterom and Strackee's formula: the mean of 1/p over its samples), the
// environment map's, and the choice among emitters in proportion to their powers.
#include "lights/emitters.h"
#include "lights/kinds.h"
#include "lights/triangle_lanes.h"
#include "sampling/rng.h"
#include "scene/light.h"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>

using namespace symphong;

namespace {

Light pointLight(Vec3 position, Color intensity) {
    Light l;
    l.type = Light::Type::Point;
    l.position = position;
    l.intensity = intensity;
    return l;
}

/// One emissive triangle (material 0) and a non-emissive one (material 1).
Scene triangleScene() {
    Scene s;
    PhongMaterial lamp, wall;
    lamp.name = "lamp", lamp.emission = Color(2.0, 1.0, 0.5), lamp.rhoD = Color(0.0);
    wall.name = "wall", wall.rhoD = Color(0.5);
    s.materials = {lamp, wall};
    s.positions = {Vec3(-0.5, 2, -0.3), Vec3(0.6, 2, -0.4), Vec3(0.1, 2, 0.7), Vec3(-5, 0, -5), Vec3(5, 0, -5), Vec3(0, 0, 5)};
    Triangle t0, t1;
    t0.v = {0, 1, 2};  // its normal cross(v1 - v0, v2 - v0) points down, towards the floor
    t0.material = 0;
    t1.v = {3, 5, 4};
    t1.material = 1;
    s.triangles = {t0, t1};
    return s;
}

double triangleArea(const Scene& s, const Triangle& t, Vec3& normal) {
    const Vec3 c = cross(s.positions[t.v[1]] - s.positions[t.v[0]], s.positions[t.v[2]] - s.positions[t.v[0]]);
    normal = normalize(c);
    return 0.5 * length(c);
}

/// A point light of intensity 3 at (0, 1, 0) and a sun of 0.5 shining down, added to the scene; every
/// triangle's area and unit normal, as SceneEmitters takes them.
void addPointLightAndSun(Scene& scene, std::vector<double>& areas, std::vector<Vec3>& normals) {
    scene.lights = {pointLight(Vec3(0, 1, 0), Color(3.0))};
    Light sun;
    sun.type = Light::Type::Directional, sun.direction = Vec3(0, -1, 0), sun.intensity = Color(0.5);
    scene.lights.push_back(sun);
    for (const Triangle& t : scene.triangles) {
        Vec3 n;
        areas.push_back(triangleArea(scene, t, n));
        normals.push_back(n);
    }
}

/// Solid angle of triangle (a, b, c) seen from p (Van Oosterom and Strackee 1983).
double solidAngle(Vec3 a, Vec3 b, Vec3 c, Vec3 p) {
    a = a - p, b = b - p, c = c - p;
    const double la = length(a), lb = length(b), lc = length(c);
    const double num = std::abs(dot(a, cross(b, c)));
    const double den = la * lb * lc + dot(a, b) * lc + dot(a, c) * lb + dot(b, c) * la;
    return 2 * std::atan2(num, den);
}

}  // namespace

TEST(Emitters, PointLightGivesIntensityOverDistanceSquared) {
    const auto e = makePointEmitter(pointLight(Vec3(1, 3, -2), Color(4, 2, 1)));
    EXPECT_TRUE(e->isDelta());
    EXPECT_NEAR(e->power(10), 4 * kPi * luminance(Color(4, 2, 1)), 1e-12);
    for (const Vec3 p : {Vec3(0, 0, 0), Vec3(2, -1, 5), Vec3(1, 2.5, -2)}) {
        EmitterSample s;
        ASSERT_TRUE(e->sample(p, {0.3, 0.7}, 0.25, s));
        const double d2 = dot(Vec3(1, 3, -2) - p, Vec3(1, 3, -2) - p);
        EXPECT_NEAR(s.radiance.x, 4 / d2, 1e-12);
        EXPECT_NEAR(s.radiance.z, 1 / d2, 1e-12);
        EXPECT_NEAR(dot(s.wi, normalize(Vec3(1, 3, -2) - p)), 1.0, 1e-12);
        EXPECT_EQ(s.pdf, 0.25) << "a delta emitter's density is its choice probability";
        EXPECT_FALSE(s.toInfinity);
        EXPECT_EQ(s.target, Vec3(1, 3, -2));
    }
}

TEST(Emitters, SpotLightFallsOffAsItsSmoothstepBetweenTheCones) {
    Light l = pointLight(Vec3(0, 4, 0), Color(8.0));
    l.type = Light::Type::Spot;
    l.direction = Vec3(0, -1, 0);
    l.cosInner = std::cos(20 * kPi / 180), l.cosOuter = std::cos(40 * kPi / 180);
    const auto e = makeSpotEmitter(l);
    EXPECT_NEAR(e->power(1), 2 * kPi * 8 * (1 - 0.5 * (l.cosInner + l.cosOuter)), 1e-12);
    for (double deg : {0.0, 10.0, 19.9, 25.0, 30.0, 35.0, 39.9, 45.0, 80.0}) {
        const double a = deg * kPi / 180;
        const Vec3 p(4 * std::tan(a), 0, 0);  // on the floor, at angle `deg` from the axis
        EmitterSample s;
        const bool lit = e->sample(p, {0.5, 0.5}, 1.0, s);
        const double d2 = 16 + p.x * p.x;
        // smoothstep of the cosine between the cones, written out here
        const double t = std::clamp((std::cos(a) - l.cosOuter) / (l.cosInner - l.cosOuter), 0.0, 1.0);
        const double expected = 8 / d2 * t * t * (3 - 2 * t);
        if (expected == 0) {
            EXPECT_FALSE(lit) << deg;
        } else {
            ASSERT_TRUE(lit) << deg;
            EXPECT_NEAR(s.radiance.y, expected, 1e-12 * expected) << deg;
        }
    }
}

TEST(Emitters, DirectionalLightArrivesAlongOneDirectionFromInfinity) {
    Light l;
    l.type = Light::Type::Directional;
    l.direction = normalize(Vec3(1, -2, 0.5));
    l.intensity = Color(1.5, 1.0, 0.5);
    const auto e = makeDirectionalEmitter(l);
    EXPECT_NEAR(e->power(3), kPi * 9 * luminance(l.intensity), 1e-12);
    EmitterSample s;
    ASSERT_TRUE(e->sample(Vec3(7, 1, 2), {0.1, 0.9}, 0.5, s));
    EXPECT_EQ(s.wi, -l.direction);
    EXPECT_EQ(s.radiance, l.intensity);
    EXPECT_TRUE(s.toInfinity);
}

TEST(Emitters, TriangleDensityIsOneOverItsSolidAngleAndMatchesTheHitDensity) {
    const Scene scene = triangleScene();
    Vec3 normal;
    const double area = triangleArea(scene, scene.triangles[0], normal);
    const TriangleLight e = makeTriangleLight(scene, 0, area, normal);
    EXPECT_NEAR(trianglePower(e), area * luminance(Color(2, 1, 0.5)), 1e-12);
    const Vec3 p(0.3, 0.1, -0.2);
    Rng rng(7, 3);
    const int n = 200000;
    double sumInvPdf = 0, sumSq = 0;
    for (int i = 0; i < n; ++i) {
        EmitterSample s;
        ASSERT_TRUE(sampleTriangleLight(e, scene, p, rng.uniform2(), s));
        const double dist = length(s.target - p);
        // The density of a path that hit the same point along the same direction: the other code path.
        EXPECT_NEAR(triangleLightPdfOfHit(e, s.wi * 2.0, dist / 2.0), s.pdf, 1e-9 * s.pdf);
        EXPECT_EQ(s.radiance, Color(2, 1, 0.5));
        sumInvPdf += 1 / s.pdf;
        sumSq += 1 / (s.pdf * s.pdf);
    }
    const double mean = sumInvPdf / n, se = std::sqrt((sumSq / n - mean * mean) / n);
    const auto& t = scene.triangles[0];
    const double omega = solidAngle(scene.positions[t.v[0]], scene.positions[t.v[1]], scene.positions[t.v[2]], p);
    EXPECT_NEAR(mean, omega, 4 * se) << "E[1/p] is the solid angle the triangle subtends";
    EmitterSample behind;
    EXPECT_FALSE(sampleTriangleLight(e, scene, Vec3(0, 3, 0), {0.3, 0.3}, behind)) << "a point behind the emitting side gets nothing";
}

TEST(Emitters, EnvironmentMapDensityMatchesItsHitDensity) {
    std::vector<float> texels(8 * 4 * 3, 0.1f);
    texels[3 * (1 * 8 + 5)] = 40.0f;  // a bright texel
    EnvironmentMap map(Texture("sky", 8, 4, 3, texels), 1.0, 30.0, EnvironmentMap::Filter::Nearest);
    Scene scene;
    scene.environmentMap = map;
    const auto e = makeBackgroundEmitter(scene);
    EXPECT_TRUE(e->isBackground());
    EXPECT_NEAR(e->power(2), kPi * 4 * map.luminanceIntegral(), 1e-9);
    Rng rng(11, 5);
    for (int i = 0; i < 2000; ++i) {
        EmitterSample s;
        if (!e->sample(Vec3(0, 0, 0), rng.uniform2(), 0.4, s)) continue;
        EXPECT_NEAR(e->pdfOfHit(s.wi, std::numeric_limits<double>::infinity(), 0.4), s.pdf, 1e-9 * s.pdf);
        EXPECT_TRUE(s.radianceLater) << "the map is looked up after the shadow ray";
        EXPECT_TRUE(s.toInfinity);
    }
}

TEST(Emitters, SkyAndConstantBackgroundsAreSeenButNeverSampled) {
    Scene scene;
    scene.environment = Color(0.2, 0.3, 0.4);
    const auto constant = makeBackgroundEmitter(scene);
    EXPECT_EQ(constant->backgroundRadiance(Vec3(0, 1, 0)), Color(0.2, 0.3, 0.4));
    EXPECT_EQ(constant->power(100), 0.0);
    scene.sky = Sky{};
    const auto sky = makeBackgroundEmitter(scene);
    EXPECT_EQ(sky->backgroundRadiance(Vec3(0, 1, 0)), scene.sky->zenith);
    EXPECT_EQ(sky->power(100), 0.0);
    EmitterSample s;
    EXPECT_FALSE(sky->sample(Vec3(0, 0, 0), {0.5, 0.5}, 1.0, s));
}

TEST(Emitters, LightSamplingChoosesEmittersInProportionToTheirPowers) {
    Scene scene = triangleScene();
    std::vector<double> areas;
    std::vector<Vec3> normals;
    addPointLightAndSun(scene, areas, normals);
    Vec3 lo, hi;
    scene.bounds(lo, hi);
    const double r = 0.5 * length(hi - lo);
    const double pTri = areas[0] * luminance(Color(2, 1, 0.5)), pPoint = 4 * kPi * 3, pSun = kPi * r * r * 0.5;
    const SceneEmitters all(scene, areas, normals, true);
    EXPECT_NEAR(all.triangleProbability(0), pTri / (pTri + pPoint + pSun), 1e-12);
    EXPECT_EQ(all.triangleProbability(1), 0.0) << "a wall does not emit";
    EXPECT_FALSE(all.emits(1));
    EXPECT_TRUE(all.emits(0));
    // Light sampling's density of the triangle, reached by a path, is pick / area x d^2 / cos.
    const Vec3 from(0.3, 0.1, -0.2);
    EmitterSample st;
    for (int i = 0; i < 1000 && !(st.pdf > 0 && !st.delta && !st.toInfinity && length(st.target - from) > 0); ++i) {
        st = EmitterSample{};
        if (!all.sample(from, {(i + 0.5) / 1000, 0.37}, st)) st.pdf = 0;
    }
    ASSERT_GT(st.pdf, 0) << "light sampling picks the triangle";
    EXPECT_NEAR(all.trianglePdfOfHit(0, st.wi, length(st.target - from)), st.pdf, 1e-9 * st.pdf);
    EXPECT_EQ(all.trianglePdfOfHit(1, st.wi, 1.0), 0.0);
    EXPECT_TRUE(all.samplesTriangles());
    // Without the emitters a path can hit (no NEE of triangles), only the delta lights are sampled.
    const SceneEmitters deltaOnly(scene, areas, normals, false);
    EXPECT_FALSE(deltaOnly.samplesTriangles());
    EXPECT_EQ(deltaOnly.triangleProbability(0), 0.0);
    // Every light sampled is a delta light: the point light (toward (0,1,0), not to infinity) or the sun.
    int picks[2] = {0, 0};
    for (int i = 0; i < 1000; ++i) {
        EmitterSample s;
        ASSERT_TRUE(deltaOnly.sample(Vec3(0.2, -1, 0.1), {(i + 0.5) / 1000, 0.5}, s));
        EXPECT_TRUE(s.delta);
        ++picks[s.toInfinity ? 1 : 0];
        EXPECT_NEAR(s.pdf, s.toInfinity ? pSun / (pPoint + pSun) : pPoint / (pPoint + pSun), 1e-12) << "a delta light's pdf is its pick";
    }
    EXPECT_NEAR(picks[0] / 1000.0, pPoint / (pPoint + pSun), 2e-3);
}

namespace {

/// Every field of two light samples the same, bit for bit (where they were sampled).
void expectSameSample(const EmitterSample& a, const EmitterSample& b, const std::string& where) {
    const auto bits = [](double x) { return std::bit_cast<std::uint64_t>(x); };
    const auto same = [&](const Vec3& x, const Vec3& y) {
        return bits(x.x) == bits(y.x) && bits(x.y) == bits(y.y) && bits(x.z) == bits(y.z);
    };
    EXPECT_TRUE(same(a.wi, b.wi) && same(a.target, b.target) && same(a.radiance, b.radiance) && bits(a.pdf) == bits(b.pdf)) << where;
    EXPECT_TRUE(a.toInfinity == b.toInfinity && a.delta == b.delta && a.radianceLater == b.radianceLater) << where;
}

}  // namespace

// lights/triangle_lanes.h: many light samples at once, each towards its own triangle, in vector lanes where the
// processor has them, against sampleTriangleLight one at a time: the same answers and the same samples bit for
// bit, with points in front of and behind the triangles, a point at a corner that the sample lands on (distance
// 0), and counts that leave a part of a lane group empty.
TEST(TriangleLanes, SamplesEqualTheScalarSampleBitForBit) {
    Rng rng(47, 9);
    const Scene scene;  // untextured lights never read it
    std::vector<TriangleLight> table(37);
    for (TriangleLight& t : table) {
        const auto corner = [&] { return Vec3(rng.uniform() * 4 - 2, rng.uniform() * 4 - 2, rng.uniform() * 4 - 2); };
        t.v0 = corner(), t.v1 = corner(), t.v2 = corner();
        const Vec3 c = cross(t.v1 - t.v0, t.v2 - t.v0);
        t.normal = normalize(c);
        t.area = 0.5 * length(c);
        t.pick = 0.1 + rng.uniform();
        t.pickOverArea = t.pick / t.area;
        t.emission = Color(rng.uniform(), rng.uniform() * 3, 0.5);
    }
    std::vector<std::uint32_t> rows;
    std::vector<Vec3> points;
    std::vector<double> us, vs;
    for (int i = 0; i < 5000; ++i) {
        rows.push_back(rng.bits() % table.size());
        points.emplace_back(rng.uniform() * 6 - 3, rng.uniform() * 6 - 3, rng.uniform() * 6 - 3);
        us.push_back(rng.uniform());
        vs.push_back(rng.uniform());
    }
    rows.insert(rows.begin() + 3, 5);  // u = 0 lands on corner v0: the point there is at distance 0
    points.insert(points.begin() + 3, table[5].v0);
    us.insert(us.begin() + 3, 0.0);
    vs.insert(vs.begin() + 3, 0.25);
    const bool lanes = triangleLanesAvailable();
    if (!lanes) std::printf("[ NOTE     ] no AVX-512 here: the dispatching call runs the scalar form\n");
    std::size_t sampledCount = 0, refused = 0;
    for (std::size_t n : {std::size_t{0}, std::size_t{1}, std::size_t{4}, std::size_t{8}, std::size_t{13}, rows.size()}) {
        std::vector<EmitterSample> viaCall(n), viaLanes(n);
        std::unique_ptr<bool[]> okCall(new bool[n + 1]), okLanes(new bool[n + 1]);
        sampleTriangleLights(table.data(), rows.data(), scene, points.data(), us.data(), vs.data(), n, viaCall.data(), okCall.get());
        if (lanes)
            detail::sampleTriangleLightsLanes(table.data(), rows.data(), scene, points.data(), us.data(), vs.data(), n, viaLanes.data(),
                                              okLanes.get());
        for (std::size_t i = 0; i < n; ++i) {
            EmitterSample s;
            const bool ok = sampleTriangleLight(table[rows[i]], scene, points[i], {us[i], vs[i]}, s);
            ASSERT_EQ(okCall[i], ok) << "sample " << i << " of " << n;
            if (lanes) {
                ASSERT_EQ(okLanes[i], ok) << "lanes, sample " << i << " of " << n;
            }
            if (!ok) {
                ++refused;
                continue;
            }
            ++sampledCount;
            expectSameSample(viaCall[i], s, "sample " + std::to_string(i) + " of " + std::to_string(n));
            if (lanes) expectSameSample(viaLanes[i], s, "lanes, sample " + std::to_string(i) + " of " + std::to_string(n));
        }
    }
    EXPECT_GT(sampledCount, rows.size() / 4) << "points in front of their triangles";
    EXPECT_GT(refused, rows.size() / 4) << "points behind their triangles, and the one at a corner";
}

// SceneEmitters::sampleMany against sample() one point at a time, with two emissive triangles (the lanes'), a
// point light and a directional light (one by one) in the table: the same answers and samples bit for bit.
TEST(Emitters, SampleManyEqualsSampleOneByOne) {
    Scene scene = triangleScene();
    scene.triangles[1].material = 0;  // the floor emits too: two rows of triangles
    std::vector<double> areas;
    std::vector<Vec3> normals;
    addPointLightAndSun(scene, areas, normals);
    const SceneEmitters emitters(scene, areas, normals, true);
    Rng rng(53, 2);
    constexpr std::size_t kPoints = 3000;
    std::vector<Vec3> points;
    std::vector<double> us, vs;
    for (std::size_t i = 0; i < kPoints; ++i) {
        points.emplace_back(rng.uniform() * 4 - 2, rng.uniform() * 3 - 0.5, rng.uniform() * 4 - 2);
        us.push_back(rng.uniform());
        vs.push_back(rng.uniform());
    }
    std::vector<EmitterSample> many(kPoints);
    std::unique_ptr<bool[]> sampled(new bool[kPoints]);
    emitters.sampleMany(points.data(), us.data(), vs.data(), kPoints, many.data(), sampled.get());
    std::size_t delta = 0, area = 0;
    for (std::size_t i = 0; i < kPoints; ++i) {
        EmitterSample s;
        const bool ok = emitters.sample(points[i], {us[i], vs[i]}, s);
        ASSERT_EQ(sampled[i], ok) << "point " << i;
        if (!ok) continue;
        expectSameSample(many[i], s, "point " + std::to_string(i));
        (s.delta ? delta : area) += 1;
    }
    EXPECT_GT(delta, kPoints / 20) << "the lights sampled one by one";
    EXPECT_GT(area, kPoints / 20) << "the triangles sampled in lanes";
}
