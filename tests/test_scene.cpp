// Scene loading: the built-in Cornell box, every OBJ in the shared scenes (including the quirky and
// the malformed ones), and JSON scene files with their errors.
#include "io/input_error.h"
#include "scene/scene.h"
#include "test_util.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <random>
#include <vector>

using namespace symphong;
namespace fs = std::filesystem;

namespace {

std::string scene(const std::string& rel) { return test::scenesDir() + "/" + rel; }

bool anyWarningContains(const Scene& s, const std::string& text) {
    for (const auto& w : s.warnings)
        if (w.find(text) != std::string::npos) return true;
    return false;
}

std::string errorOf(const std::string& spec) {
    try {
        loadScene(spec);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST(CornellBuiltin, HasTheOriginalGeometryAndAGlossyTallBlock) {
    const Scene s = loadScene("cornell");
    EXPECT_EQ(s.triangles.size(), 32u);
    Vec3 lo, hi;
    s.bounds(lo, hi);
    EXPECT_DOUBLE_EQ(lo.x, 0);
    EXPECT_DOUBLE_EQ(hi.x, 556);
    EXPECT_DOUBLE_EQ(hi.y, 548.8);
    const int tall = s.findMaterial("tallBlock");
    ASSERT_GE(tall, 0);
    EXPECT_TRUE(s.materials[tall].hasSpecular());
    EXPECT_GT(luminance(s.materials[tall].rhoD), 0);
    EXPECT_TRUE(s.hasEmitter());
    EXPECT_TRUE(s.warnings.empty());
    // The light is 130 x 105.
    double lightArea = 0;
    for (const auto& t : s.triangles)
        if (s.materials[t.material].isEmissive())
            lightArea += 0.5 * length(cross(s.positions[t.v[1]] - s.positions[t.v[0]], s.positions[t.v[2]] - s.positions[t.v[0]]));
    EXPECT_NEAR(lightArea, 130.0 * 105.0, 1e-9);
}

TEST(SceneBounds, AreTheTrianglesVerticesOnlyWhereverTheOutputsLie) {
    // Random triangles over part of a vertex list whose other vertices lie far outside: the bounds are the
    // coordinate-wise extremes of the referenced vertices (found here by std::minmax over them), also when
    // the outputs are vertices of the scene itself (bounds reads every vertex before it writes).
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    Scene s;
    for (int i = 0; i < 200; ++i) s.positions.emplace_back(u(rng) * 10 - 3, u(rng) * 4 - 8, u(rng) * 2 + 1);
    s.positions.emplace_back(1e6, -1e6, 1e6);
    s.positions.emplace_back(-1e6, 1e6, -1e6);
    for (int i = 0; i < 50; ++i) {
        Triangle t;
        for (auto& v : t.v) v = static_cast<std::uint32_t>(rng() % 200);
        s.triangles.push_back(t);
    }
    Vec3 want[2];
    for (int axis = 0; axis < 3; ++axis) {
        std::vector<double> c;
        for (const Triangle& t : s.triangles)
            for (std::uint32_t v : t.v) c.push_back(s.positions[v][axis]);
        const auto [lo, hi] = std::minmax_element(c.begin(), c.end());
        want[0][axis] = *lo, want[1][axis] = *hi;
    }
    Vec3 lo, hi;
    s.bounds(lo, hi);
    for (int axis = 0; axis < 3; ++axis) {
        EXPECT_EQ(lo[axis], want[0][axis]) << axis;
        EXPECT_EQ(hi[axis], want[1][axis]) << axis;
    }
    // Into two vertices of the scene itself, the lowest and the highest in every coordinate.
    Scene t = s;
    t.positions[0] = lo - Vec3(1.0), t.positions[1] = hi + Vec3(1.0);
    t.triangles.push_back(Triangle{{0, 1, 2}});
    const Vec3 want0 = t.positions[0], want1 = t.positions[1];
    t.bounds(t.positions[0], t.positions[1]);
    for (int axis = 0; axis < 3; ++axis) {
        EXPECT_EQ(t.positions[0][axis], want0[axis]) << axis;
        EXPECT_EQ(t.positions[1][axis], want1[axis]) << axis;
    }
}

TEST(ObjScenes, McGuireBoxesLoadWithTrimmedMaterialNames) {
    SYMPHONG_REQUIRE_SCENES_DIR();
    const Scene original = loadScene(scene("cornell-box-mcguire/CornellBox-Original.obj"));
    EXPECT_EQ(original.triangles.size(), 36u);
    EXPECT_TRUE(original.hasEmitter());
    const Scene glossy = loadScene(scene("cornell-box-mcguire/CornellBox-Glossy.obj"));
    EXPECT_EQ(glossy.triangles.size(), 1112u);
    EXPECT_FALSE(glossy.normals.empty());
    const int sphere = glossy.findMaterial("sphere");
    ASSERT_GE(sphere, 0) << "'sphere' has trailing tabs in the MTL and must be trimmed";
    EXPECT_DOUBLE_EQ(glossy.materials[sphere].exponent, 32);
    EXPECT_GE(glossy.findMaterial("light"), 0) << "' newmtl light' has a leading space";
    // Kd 0.486.. + Ks 0.7 > 1: clamped, with a warning naming the material.
    EXPECT_LE(glossy.materials[sphere].rhoD.z + glossy.materials[sphere].rhoS.z, 1.0 + 1e-12);
    EXPECT_TRUE(anyWarningContains(glossy, "'sphere'"));
    const Scene spheres = loadScene(scene("cornell-box-mcguire/CornellBox-Sphere.obj"));
    EXPECT_EQ(spheres.triangles.size(), 2188u);
    EXPECT_DOUBLE_EQ(spheres.materials[spheres.findMaterial("leftSphere")].exponent, 1000);
}

TEST(ObjScenes, BunnyLoadsWithTheDefaultMaterialAndAFallbackEnvironment) {
    SYMPHONG_REQUIRE_SCENES_DIR();
    const Scene s = loadScene(scene("bunny/stanford-bunny.obj"));
    EXPECT_EQ(s.triangles.size(), 69451u);
    EXPECT_EQ(s.materials.size(), 1u);
    EXPECT_TRUE(anyWarningContains(s, "no light of any kind"));
    // The default sky and its sun, and a three-quarter view (a bare model, no emissive triangles).
    ASSERT_TRUE(s.sky.has_value());
    ASSERT_EQ(s.lights.size(), 1u);
    EXPECT_EQ(s.lights[0].type, Light::Type::Directional);
    EXPECT_LT(s.lights[0].direction.y, 0) << "the sun shines down";
    const Vec3 view = normalize(s.camera.position - s.camera.target);
    EXPECT_GT(view.x, 0.4);
    EXPECT_GT(view.y, 0.2);
    EXPECT_GT(view.z, 0.6);
    // The sky: blue overhead, brighter at the horizon, darker below.
    EXPECT_GT(s.environmentRadiance(Vec3(0, 1, 0)).z, s.environmentRadiance(Vec3(0, 1, 0)).x);
    EXPECT_GT(luminance(s.environmentRadiance(Vec3(1, 0, 0))), luminance(s.environmentRadiance(Vec3(0, 1, 0))));
    EXPECT_LT(luminance(s.environmentRadiance(Vec3(0, -1, 0))), luminance(s.environmentRadiance(Vec3(1, 0, 0))));
    // The whole bounding sphere is in view: every corner of the box projects inside the frame.
    Vec3 lo, hi;
    s.bounds(lo, hi);
    const Vec3 forward = normalize(s.camera.target - s.camera.position);
    const double tanHalf = std::tan(0.5 * s.camera.fovY * kPi / 180.0);
    for (int k = 0; k < 8; ++k) {
        const Vec3 corner(k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 4 ? hi.z : lo.z);
        const Vec3 to = corner - s.camera.position;
        const double along = dot(to, forward);
        EXPECT_LT(length(to - forward * along) / along, tanHalf) << "corner " << k << " is outside the view";
    }
}

TEST(ObjScenes, AMeshWithItsOwnLightIsSeenFromTheFront) {
    SYMPHONG_REQUIRE_SCENES_DIR();
    const Scene s = loadScene(scene("cornell-box-mcguire/CornellBox-Original.obj"));
    EXPECT_FALSE(s.sky.has_value());
    const Vec3 view = normalize(s.camera.position - s.camera.target);
    EXPECT_NEAR(view.z, 1.0, 1e-12) << "a set with light fixtures (open towards +Z) is seen from +Z";
}

TEST(ObjScenes, CornellOriginalWarnsThatNothingEmits) {
    SYMPHONG_REQUIRE_SCENES_DIR();
    const Scene s = loadScene(scene("cornell-box-original/cornell_box.obj"));
    EXPECT_EQ(s.triangles.size(), 36u);
    EXPECT_TRUE(anyWarningContains(s, "no light of any kind"));
}

TEST(ObjScenes, LenientSceneNamesItsUndefinedMaterials) {
    SYMPHONG_REQUIRE_SCENES_DIR();
    const Scene s = loadScene(scene("lenient/missing_material_file.obj"));
    EXPECT_EQ(s.triangles.size(), 36u);
    EXPECT_TRUE(anyWarningContains(s, "'white'"));
    EXPECT_TRUE(anyWarningContains(s, "'light'"));
}

TEST(ObjScenes, EveryMalformedFileIsRejectedWithFileAndLine) {
    SYMPHONG_REQUIRE_SCENES_DIR();
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"malformed/invalid-face-definition.obj", "invalid-face-definition.obj:"},
        {"malformed/issue-140-zero-face-idx.obj", "index 0"},
        {"malformed/test-nan.obj", "test-nan.obj:12: vertex coordinate 'nan'"},
        {"malformed/invalid-relative-vertex-index.obj", "invalid-relative-vertex-index.obj:1: face vertex index -4"},
        {"malformed/invalid-relative-texture-index.obj", "invalid-relative-texture-index.obj:2:"},
    };
    for (const auto& [file, expected] : cases) {
        const std::string msg = errorOf(scene(file));
        EXPECT_NE(msg.find(expected), std::string::npos) << file << " gave: '" << msg << "'";
    }
}

TEST(ObjScenes, MissingAndUnknownFilesAreInputErrors) {
    EXPECT_NE(errorOf("/nonexistent/x.obj").find("no such file"), std::string::npos);
    EXPECT_NE(errorOf("scene.fbx").find("no such file"), std::string::npos) << "an FBX is read (through Assimp): this one is missing";
    EXPECT_NE(errorOf("scene.blend").find("unknown scene"), std::string::npos);
    EXPECT_NE(errorOf(fs::temp_directory_path().string() + "/dir.obj/").find("unknown scene"), std::string::npos);
}

TEST(ObjScenes, MtlWithNegativeOrNonFiniteValuesIsRejected) {
    test::TempDir dir;
    const std::string obj = "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl a\nf 1 2 3\n";
    dir.write("m.mtl", "newmtl a\nKd 0.5 0.5 0.5\nNs -3\n");
    const std::string path = dir.write("a.obj", obj);
    EXPECT_NE(errorOf(path).find("m.mtl:3: Ns value -3 is negative"), std::string::npos) << errorOf(path);
    dir.write("m.mtl", "newmtl a\nKd 0.5 nan 0.5\n");
    EXPECT_NE(errorOf(path).find("m.mtl:2: Kd value 'nan' is not a finite number"), std::string::npos) << errorOf(path);
}

TEST(JsonScenes, BuiltinWithOverridesAndCamera) {
    test::TempDir dir;
    const std::string path = dir.write("glossy.json", R"({
        "builtin": "cornell",
        "name": "glossy100",
        "materials": {"tallBlock": {"ks": 0.7, "kd": [0.1, 0.1, 0.1], "ns": 100}},
        "camera": {"fov": 45}
    })");
    const Scene s = loadScene(path);
    EXPECT_EQ(s.name, "glossy100");
    const auto& m = s.materials[s.findMaterial("tallBlock")];
    EXPECT_DOUBLE_EQ(m.exponent, 100);
    EXPECT_DOUBLE_EQ(m.rhoS.y, 0.7);
    EXPECT_DOUBLE_EQ(s.camera.fovY, 45);
    EXPECT_DOUBLE_EQ(s.camera.position.z, -800);
}

TEST(JsonScenes, ObjRelativeToTheJsonFile) {
    SYMPHONG_REQUIRE_SCENES_DIR();
    test::TempDir dir;
    const std::string path =
        dir.write("bunny.json", R"({"obj": ")" + scene("bunny/stanford-bunny.obj") +
                                    R"(", "environment": [0.5, 0.6, 0.7], "camera": {"position": [0, 0.1, 0.4], "target": [0, 0.1, 0]}})");
    const Scene s = loadScene(path);
    EXPECT_EQ(s.environment, Color(0.5, 0.6, 0.7));
    EXPECT_FALSE(anyWarningContains(s, "no light of any kind")) << "an explicit environment is not a fallback";
    EXPECT_FALSE(s.sky.has_value());
    EXPECT_DOUBLE_EQ(s.camera.position.z, 0.4);
}

TEST(JsonScenes, ErrorsNameTheProblem) {
    test::TempDir dir;
    const std::vector<std::pair<std::string, std::string>> cases = {
        {R"({"builtin": "cornell",})", "malformed JSON"},
        {R"({"builtin": "cornell", "camra": {}})", "unknown key 'camra'"},
        {R"({"builtin": "cornell", "materials": {"tallBlock": {"ns": -5}}})", "is negative"},
        {R"({"builtin": "cornell", "materials": {"nothing": {"ns": 5}}})", "matches no material"},
        {R"({"builtin": "cornell", "materials": {"white": {"kd": [0.1, -0.2, 0.3]}}})", "negative value"},
        {R"({"builtin": "cornell", "camera": {"fov": 0}})", "fov 0"},
        {R"({"builtin": "cornell", "camera": {"position": [1, 2]}})", "array of 3 numbers"},
        {R"({"builtin": "cornell", "camera": {"up": [0, 0, 1]}})", "parallel"},
        {R"({"builtin": "sponza"})", "unknown builtin"},
        {R"({"obj": "missing.obj"})", "no such file"},
        {R"({})", "exactly one of"},
        {R"([1, 2])", "must be a JSON object"},
    };
    for (const auto& [text, expected] : cases) {
        const std::string path = dir.write("s.json", text);
        const std::string msg = errorOf(path);
        EXPECT_NE(msg.find(expected), std::string::npos) << text << " gave: '" << msg << "'";
        EXPECT_NE(msg.find("s.json"), std::string::npos) << msg;
    }
}

// The study scenes shipped in scenes/ load, with the materials they promise.
TEST(StudyScenes, AllLoad) {
    const fs::path dir = fs::path(SYMPHONG_SOURCE_DIR) / "scenes";
    int count = 0;
    for (const auto& e : fs::directory_iterator(dir)) {
        if (e.path().extension() != ".json") continue;
        if (e.path().filename() == "mcguire-glossy.json" && test::scenesDir().empty()) continue;
        const Scene s = loadScene(e.path().string());
        EXPECT_TRUE(s.hasEmitter()) << e.path();
        ++count;
    }
    EXPECT_GE(count, 4);
    const Scene g = loadScene((dir / "cornell-glossy-1000.json").string());
    EXPECT_DOUBLE_EQ(g.materials[g.findMaterial("tallBlock")].exponent, 1000);
    const Scene d = loadScene((dir / "cornell-diffuse.json").string());
    EXPECT_FALSE(d.materials[d.findMaterial("tallBlock")].hasSpecular());
}

TEST(Obj, PolygonsAreFannedIntoAllTheirTrianglesWithoutAWarning) {
    // Faces of 3, 4 and 5 corners make 1 + 2 + 3 triangles; the loader compares that with what it read
    // and warns only when they differ.
    test::TempDir dir;
    const Scene s = loadScene(dir.write("p.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 1.5 0\nf 1 2 3\nf 1 2 3 4\nf 1 2 3 5 4\n"));
    EXPECT_EQ(s.triangles.size(), 6u);
    for (const std::string& w : s.warnings) EXPECT_EQ(w.find("were read"), std::string::npos) << w;
}
