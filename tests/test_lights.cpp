// Point, spot, directional and quad lights (scene/light.h, JSON "lights"): --max-depth 1 renders of a
// diffuse floor against their closed forms, region by region within 4 standard errors (a point light:
// L = rho/pi I cos / d^2; a spot: the same times its falloff; a directional light: rho/pi E cos, and
// nothing in an occluder's shadow); lights are sampled with and without --no-nee; the JSON form and
// its errors.
#include "floor_closed_form.h"
#include "stats.h"
#include "test_util.h"

#include "io/input_error.h"
#include "compare/metrics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <optional>

using namespace symphong;

namespace {

constexpr double kAlbedo = 0.6, kFloor = 20.0;

using test::addQuad;

Scene floorScene() { return test::floorScene(kAlbedo, kFloor); }

void expectMatchesClosedForm(const Scene& scene, const std::function<std::optional<double>(const Vec3& floorPoint, const Vec3& ray)>& exact,
                             const std::string& what, int minRegions) {
    test::expectFloorMatchesClosedForm(scene, kFloor, exact, what, minRegions);
}

}  // namespace

TEST(Lights, PointLightAboveAPlaneGivesRhoOverPiICosOverDSquared) {
    Scene s = floorScene();
    Light l;
    l.type = Light::Type::Point;
    l.position = Vec3(0.1, 1.0, -0.3);
    l.intensity = Color(2.5);
    s.lights = {l};
    expectMatchesClosedForm(
        s,
        [&](const Vec3& q, const Vec3&) -> std::optional<double> {
            const Vec3 to = l.position - q;
            const double d = length(to);
            return kAlbedo / kPi * 2.5 * (to.y / d) / (d * d);
        },
        "point light", 50);
}

TEST(Lights, SpotLightIsAPointLightTimesItsFalloff) {
    Scene s = floorScene();
    Light l;
    l.type = Light::Type::Spot;
    l.position = Vec3(0.0, 1.2, -0.2);
    l.direction = normalize(Vec3(0.1, -1, 0.0));
    l.intensity = Color(3.0);
    l.cosOuter = std::cos(35 * kPi / 180), l.cosInner = std::cos(20 * kPi / 180);
    s.lights = {l};
    int dark = 0;
    expectMatchesClosedForm(
        s,
        [&](const Vec3& q, const Vec3&) -> std::optional<double> {
            const Vec3 to = l.position - q;
            const double d = length(to);
            const double falloff = spotFalloff(dot(-to / d, l.direction), l.cosInner, l.cosOuter);
            dark += falloff == 0;
            return kAlbedo / kPi * 3.0 * falloff * (to.y / d) / (d * d);
        },
        "spot light", 50);
    EXPECT_GT(dark, 1000) << "part of the floor must lie outside the cone";
}

TEST(Lights, DirectionalLightCastsASharpShadow) {
    Scene s = floorScene();
    const Vec3 dir = normalize(Vec3(0.3, -1, 0.2));
    Light l;
    l.type = Light::Type::Directional;
    l.direction = dir;
    l.intensity = Color(1.5);
    s.lights = {l};
    // A black square occluder at height 0.4, seen by no camera ray that reaches the floor regions used.
    const double h = 0.4, x0 = -0.3, x1 = 0.2, z0 = -0.6, z1 = -0.2;
    addQuad(s, Vec3(x0, h, z0), Vec3(x0, h, z1), Vec3(x1, h, z1), Vec3(x1, h, z0), 1);
    int shadowed = 0;
    expectMatchesClosedForm(
        s,
        [&](const Vec3& q, const Vec3& ray) -> std::optional<double> {
            // The camera ray must not pass through the occluder on its way to the floor.
            const Vec3 o = s.camera.position;
            const double t = (h - o.y) / ray.y;
            const Vec3 c = o + ray * t;
            if (c.x > x0 && c.x < x1 && c.z > z0 && c.z < z1) return std::nullopt;
            // Towards the light from q: does it pass through the occluder?
            const double u = h / -dir.y;
            const Vec3 p = q - dir * u;
            const bool inShadow = p.x > x0 && p.x < x1 && p.z > z0 && p.z < z1;
            shadowed += inShadow;
            return inShadow ? 0.0 : kAlbedo / kPi * 1.5 * -dir.y;
        },
        "directional light", 40);
    EXPECT_GT(shadowed, 500) << "the shadow must fall inside the tested part of the floor";
}

TEST(Lights, JsonLightsLoadAndRender) {
    test::TempDir dir;
    const std::string obj = dir.write("floor.obj", "v -5 0 -5\nv -5 0 5\nv 5 0 5\nv 5 0 -5\nf 1 2 3 4\n");
    const std::string scene = dir.write("lit.json", R"({
  "obj": "floor.obj",
  "camera": {"position": [0, 3, 3], "target": [0, 0, 0]},
  "environment": 0,
  "lights": [
    {"type": "point", "position": [0, 1, 0], "intensity": [1, 2, 3]},
    {"type": "spot", "position": [1, 1, 0], "target": [1, 0, 0], "intensity": 5, "angle": 40, "inner": 30},
    {"type": "directional", "direction": [0, -1, 0], "irradiance": 0.5},
    {"type": "quad", "corner": [-1, 2, -1], "edge1": [2, 0, 0], "edge2": [0, 0, 2], "radiance": 4}
  ]
})");
    const Scene s = loadScene(scene);
    ASSERT_EQ(s.lights.size(), 3u);
    EXPECT_EQ(s.lights[0].type, Light::Type::Point);
    EXPECT_EQ(s.lights[0].intensity, Color(1, 2, 3));
    EXPECT_EQ(s.lights[1].type, Light::Type::Spot);
    EXPECT_NEAR(s.lights[1].direction.y, -1.0, 1e-12);
    EXPECT_NEAR(s.lights[1].cosOuter, std::cos(40 * kPi / 180), 1e-12);
    EXPECT_NEAR(s.lights[1].cosInner, std::cos(30 * kPi / 180), 1e-12);
    EXPECT_EQ(s.lights[2].type, Light::Type::Directional);
    // The quad: two emissive triangles facing cross(edge1, edge2) = -y, down at the floor.
    ASSERT_EQ(s.triangles.size(), 4u);
    const Triangle& q = s.triangles[2];
    EXPECT_EQ(s.materials[q.material].emission, Color(4.0));
    const Vec3 n = cross(s.positions[q.v[1]] - s.positions[q.v[0]], s.positions[q.v[2]] - s.positions[q.v[0]]);
    EXPECT_LT(n.y, 0);
    EXPECT_TRUE(s.warnings.empty()) << "lights are emitters: no white-environment fallback";
    const RenderResult r = test::renderTiny(s, "cosine", 8, 4, 1);
    double sum = 0;
    for (const Color& c : r.image.pixels) sum += luminance(c);
    EXPECT_GT(sum, 0);
}

TEST(Lights, OnlyALightAndNoEmissiveTriangleIsNoFallback) {
    test::TempDir dir;
    dir.write("floor.obj", "v -5 0 -5\nv -5 0 5\nv 5 0 5\nv 5 0 -5\nf 1 2 3 4\n");
    const Scene s =
        loadScene(dir.write("p.json", R"({"obj": "floor.obj", "lights": [{"type": "point", "position": [0, 1, 0], "intensity": 1}]})"));
    EXPECT_EQ(s.environment, Color(0.0));
    EXPECT_TRUE(s.warnings.empty());
}

TEST(Lights, BadLightsNameTheElement) {
    test::TempDir dir;
    dir.write("floor.obj", "v -5 0 -5\nv -5 0 5\nv 5 0 5\nv 5 0 -5\nf 1 2 3 4\n");
    const auto expectError = [&](const std::string& lights, const std::string& fragment) {
        const std::string path = dir.write("bad.json", R"({"obj": "floor.obj", "lights": )" + lights + "}");
        try {
            loadScene(path);
            ADD_FAILURE() << "accepted: " << lights;
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
        }
    };
    expectError(R"({"type": "point"})", "\"lights\" must be an array");
    expectError(R"([{"type": "laser", "position": [0, 1, 0]}])", "lights[0].type 'laser' is not a light type");
    expectError(R"([{"position": [0, 1, 0]}])", "lights[0] must be an object with a \"type\"");
    expectError(R"([{"type": "point", "position": [0, 1, 0]}])", "lights[0] (point) needs \"intensity\"");
    expectError(R"([{"type": "point", "intensity": 1}])", "lights[0] (point) needs \"position\"");
    expectError(R"([{"type": "point", "position": [0, 1, 0], "intensity": -1}])", "lights[0].intensity has a negative value");
    expectError(R"([{"type": "point", "position": [0, 1, 0], "intensity": 1, "colour": 2}])", "unknown key 'colour' in lights[0]");
    expectError(R"([{"type": "point", "position": [0, 1, 0], "intensity": 1}, {"type": "spot", "position": [0, 1, 0], "intensity": 1}])",
                "lights[1] (spot) needs exactly one of \"direction\" and \"target\"");
    expectError(R"([{"type": "spot", "position": [0, 1, 0], "direction": [0, -1, 0], "intensity": 1, "angle": 120}])",
                "lights[0].angle = 120 must lie in (0, 90]");
    expectError(R"([{"type": "spot", "position": [0, 1, 0], "direction": [0, -1, 0], "intensity": 1, "angle": 20, "inner": 25}])",
                "lights[0].inner = 25 must lie in [0, angle)");
    expectError(R"([{"type": "directional", "direction": [0, 0, 0], "irradiance": 1}])", "lights[0]: the direction is zero");
    expectError(R"([{"type": "directional", "irradiance": 1}])", "lights[0] (directional) needs \"direction\"");
    expectError(R"([{"type": "quad", "corner": [0, 1, 0], "edge1": [1, 0, 0], "edge2": [2, 0, 0], "radiance": 1}])",
                "lights[0] (quad): edge1 and edge2 span no area");
    expectError(R"([{"type": "quad", "corner": [0, 1, 0], "edge1": [1, 0, 0], "radiance": 1}])", "lights[0] (quad) needs \"edge2\"");
}

// Several lights and an emissive triangle together: light sampling picks one of them per vertex (with
// its probability), so the image is the sum of the images of each alone, within statistics.
TEST(Lights, LightsAddUp) {
    Scene base = floorScene();
    PhongMaterial glow;
    glow.name = "glow", glow.emission = Color(3.0);
    base.materials.push_back(glow);
    Scene withQuad = base;
    addQuad(withQuad, Vec3(0.3, 0.8, -0.5), Vec3(0.6, 0.8, -0.5), Vec3(0.6, 0.8, -0.2), Vec3(0.3, 0.8, -0.2), 2);  // faces down
    Light point, sun;
    point.type = Light::Type::Point, point.position = Vec3(-0.4, 0.9, 0), point.intensity = Color(1.0, 2.0, 0.5);
    sun.type = Light::Type::Directional, sun.direction = normalize(Vec3(-0.5, -1, 0.1)), sun.intensity = Color(0.3);
    Scene all = withQuad;
    all.lights = {point, sun};
    Scene onlyPoint = base, onlySun = base;
    onlyPoint.lights = {point};
    onlySun.lights = {sun};
    const auto mean = [](const Scene& s, bool nee) {
        const Accel accel(s);
        const auto est = makeEstimator("cosine");
        RenderSettings rs;
        rs.width = rs.height = 24;
        rs.spp = 1024;
        rs.seed = 9;
        rs.sampler = "independent";
        rs.trace.maxDepth = 1;
        rs.trace.nextEvent = nee;
        return test::imageMeanAndError(render(s, accel, *est, rs));
    };
    for (bool nee : {true, false}) {
        const auto [a, ea] = mean(all, nee);
        const auto [q, eq] = mean(withQuad, nee);
        const auto [p, ep] = mean(onlyPoint, nee);
        const auto [s, es] = mean(onlySun, nee);
        const double se = std::sqrt(ea * ea + eq * eq + ep * ep + es * es);
        EXPECT_GT(q, 0.005) << "the quad lights the floor";
        EXPECT_LT(std::abs(a - (q + p + s)), 4 * se)
            << (nee ? "with" : "without") << " NEE: all " << a << " vs the sum " << q + p + s << " +- " << se;
        EXPECT_LT(se, 0.01 * a);
    }
}
