// Formats through Assimp (scene/assimp_loader.cpp): the classic Cornell box written by Assimp's own
// exporters as glTF (.gltf, .glb), Collada, PLY and 3DS loads with the OBJ's geometry; where the
// format keeps material names, a JSON scene naming it as "mesh" renders the OBJ's mean radiance within
// statistics; a hand-written glTF checks the material table (metallic-roughness), the emissive
// strength, the camera and a punctual light; bad files are bad input.
#include "stats.h"
#include "test_util.h"

#include "io/files.h"
#include "io/input_error.h"
#include "compare/metrics.h"

#include <assimp/postprocess.h>
#include <fmt/format.h>
#include <assimp/scene.h>
#include <gtest/gtest.h>
#include <assimp/Exporter.hpp>
#include <assimp/Importer.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <thread>

using namespace symphong;

namespace {

const std::string kClassic = std::string(SYMPHONG_SOURCE_DIR) + "/scenes/cornell-classic.obj";

/// Writes the classic box through Assimp's exporter `format` into `dir`; returns the file's path.
std::string exportClassic(const test::TempDir& dir, const char* format, const char* extension) {
    Assimp::Importer importer;
    const aiScene* scene = importer.ReadFile(kClassic, aiProcess_Triangulate);
    EXPECT_NE(scene, nullptr) << importer.GetErrorString();
    Assimp::Exporter exporter;
    const std::string out = dir.file(std::string("classic.") + extension);
    EXPECT_EQ(exporter.Export(scene, format, out), AI_SUCCESS) << exporter.GetErrorString();
    return out;
}

RenderResult renderSmall(const Scene& s) {
    const Accel accel(s);
    const auto est = makeEstimator("cosine");
    RenderSettings rs;
    rs.width = rs.height = 32;
    rs.spp = 64;
    rs.seed = 4;
    rs.sampler = "independent";
    return render(s, accel, *est, rs);
}

}  // namespace

TEST(Assimp, ExportedFormatsLoadWithTheObjGeometry) {
    test::TempDir dir;
    const Scene obj = loadScene(kClassic);
    Vec3 lo0, hi0;
    obj.bounds(lo0, hi0);
    for (const auto& [format, ext] : {std::pair{"glb2", "glb"}, std::pair{"gltf2", "gltf"}, std::pair{"collada", "dae"},
                                      std::pair{"ply", "ply"}, std::pair{"3ds", "3ds"}}) {
        // (Not FBX: Assimp 5.2 cannot read back the FBX its own exporter writes: "FBX-Tokenize ... block
        // offset is out of range".)
        const std::string file = exportClassic(dir, format, ext);
        const Scene s = loadScene(file);
        EXPECT_EQ(s.triangles.size(), obj.triangles.size()) << file;
        Vec3 lo, hi;
        s.bounds(lo, hi);
        if (std::string(ext) == "3ds") {
            // 3DS is z-up: Assimp's exporter turns the y-up box about the x axis. The extents remain.
            const Vec3 e = hi - lo, e0 = hi0 - lo0;
            std::array<double, 3> a{e.x, e.y, e.z}, b{e0.x, e0.y, e0.z};
            std::sort(a.begin(), a.end()), std::sort(b.begin(), b.end());
            for (int k = 0; k < 3; ++k) EXPECT_NEAR(a[k], b[k], 1e-3) << file << ": the box's extents changed";
        } else {
            EXPECT_LT(length(lo - lo0) + length(hi - hi0), 1e-3) << file << ": the bounding box moved";
        }
        double area = 0, area0 = 0;
        for (const Scene* sc : {&s, &obj})
            for (const Triangle& t : sc->triangles)
                (sc == &s ? area : area0) +=
                    0.5 * length(cross(sc->positions[t.v[1]] - sc->positions[t.v[0]], sc->positions[t.v[2]] - sc->positions[t.v[0]]));
        EXPECT_NEAR(area, area0, 1e-6 * area0) << file << ": the surface area differs";
    }
}

// Formats that keep material names: a JSON scene sets the OBJ's materials (the exporters turn Phong
// into their own models) and the OBJ's camera, and renders the OBJ's mean radiance.
TEST(Assimp, JsonMeshRendersTheSameMeanRadianceAsTheObj) {
    test::TempDir dir;
    const std::string materials = R"("materials": {
      "white": {"kd": [0.725, 0.71, 0.68], "ks": 0, "ns": 1, "ke": 0},
      "red": {"kd": [0.63, 0.065, 0.05], "ks": 0, "ns": 1, "ke": 0},
      "green": {"kd": [0.14, 0.45, 0.091], "ks": 0, "ns": 1, "ke": 0},
      "light": {"kd": 0, "ks": 0, "ns": 1, "ke": [17, 12, 4]}},
    "camera": {"position": [278, 273, -800], "target": [278, 273, 0], "up": [0, 1, 0], "fov": 39.3}, "environment": 0)";
    const auto [mean0, se0] =
        test::imageMeanAndError(renderSmall(loadScene(std::string(SYMPHONG_SOURCE_DIR) + "/scenes/cornell-classic.json")));
    for (const auto& [format, ext] : {std::pair{"glb2", "glb"}, std::pair{"collada", "dae"}}) {
        const std::string file = exportClassic(dir, format, ext);
        const std::string json =
            dir.write(std::string("via-") + ext + ".json", std::string(R"({"mesh": "classic.)") + ext + R"(", )" + materials + "}");
        const Scene s = loadScene(json);
        const auto [mean, se] = test::imageMeanAndError(renderSmall(s));
        EXPECT_LT(std::abs(mean - mean0), 4 * std::sqrt(se * se + se0 * se0)) << file << ": " << mean << " against the OBJ's " << mean0;
        EXPECT_LT(se, 0.02 * mean);
    }
}

// A glTF written by hand: one triangle with a metallic-roughness material (base 0.8/0.6/0.4, metallic
// 0.25, roughness 0.5), emissive (1, 0.5, 0) at strength 4, a camera with yfov 0.6 rad at (0, 1, 5)
// and a punctual point light of intensity 10 at (0, 3, 0).
TEST(Assimp, GltfMaterialCameraAndLightFollowTheTable) {
    test::TempDir dir;
    const std::string gltf = dir.write("tri.gltf", R"({
  "asset": {"version": "2.0"},
  "extensionsUsed": ["KHR_lights_punctual", "KHR_materials_emissive_strength"],
  "scene": 0,
  "scenes": [{"nodes": [0, 1, 2]}],
  "nodes": [
    {"mesh": 0},
    {"camera": 0, "translation": [0, 1, 5]},
    {"extensions": {"KHR_lights_punctual": {"light": 0}}, "translation": [0, 3, 0]}
  ],
  "cameras": [{"type": "perspective", "perspective": {"yfov": 0.6, "aspectRatio": 1.5, "znear": 0.1}}],
  "extensions": {"KHR_lights_punctual": {"lights": [{"type": "point", "color": [1, 1, 1], "intensity": 10}]}},
  "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "material": 0}]}],
  "materials": [{"name": "metal", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.6, 0.4, 1], "metallicFactor": 0.25, "roughnessFactor": 0.5},
                 "emissiveFactor": [1, 0.5, 0], "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 4}}}],
  "buffers": [{"byteLength": 36, "uri": "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAAAAAAIC/"}],
  "bufferViews": [{"buffer": 0, "byteLength": 36}],
  "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, -1], "max": [1, 0, 0]}]
})");
    const Scene s = loadScene(gltf);
    ASSERT_EQ(s.triangles.size(), 1u);
    const PhongMaterial& m = s.materials[s.triangles[0].material];
    EXPECT_EQ(m.name, "metal");
    EXPECT_NEAR(m.rhoD.x, 0.8 * 0.75 * 0.96, 1e-6);  // b (1 - m) (1 - F0): the dielectric's diffuse part
    EXPECT_NEAR(m.rhoD.z, 0.4 * 0.75 * 0.96, 1e-6);
    EXPECT_NEAR(m.rhoS.x, 0.04 * 0.75 + 0.8 * 0.25, 1e-6);
    EXPECT_NEAR(m.exponent, 2.0 / std::pow(0.25, 2) - 2.0, 1e-3);  // alpha = roughness^2 = 0.25
    EXPECT_NEAR(m.emission.x, 4.0, 1e-6);
    EXPECT_NEAR(m.emission.y, 2.0, 1e-6);
    EXPECT_NEAR(s.camera.position.y, 1.0, 1e-6);
    EXPECT_NEAR(s.camera.position.z, 5.0, 1e-6);
    EXPECT_LT(s.camera.target.z, s.camera.position.z) << "a glTF camera looks down its -z";
    EXPECT_NEAR(s.camera.fovY, 0.6 * 180 / kPi, 0.01) << "the file's vertical field of view";
    ASSERT_EQ(s.lights.size(), 1u);
    EXPECT_EQ(s.lights[0].type, Light::Type::Point);
    EXPECT_NEAR(s.lights[0].position.y, 3.0, 1e-6);
    EXPECT_GT(s.lights[0].intensity.x, 0);
}

// glTF's dielectric F0 by hand from the extensions' definitions: KHR_materials_specular's
// specularColorFactor 0 (Blender's "Specular 0") leaves a purely diffuse material of the base colour, as its
// OBJ export is; KHR_materials_ior 2.0 gives F0 = ((2 - 1) / (2 + 1))^2 = 1/9, times specularFactor 0.5.
TEST(Assimp, GltfSpecularAndIorExtensionsSetTheDielectricReflectance) {
    test::TempDir dir;
    const auto file = [&](const std::string& name, const std::string& extensions) {
        return dir.write(name, R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
  "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "material": 0}]}],
  "materials": [{"name": "m", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.6, 0.4, 1], "metallicFactor": 0, "roughnessFactor": 1},
                 "extensions": {)" + extensions + R"(}}],
  "buffers": [{"byteLength": 36, "uri": "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAAAAAAIC/"}],
  "bufferViews": [{"buffer": 0, "byteLength": 36}],
  "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, -1], "max": [1, 0, 0]}]})");
    };
    const PhongMaterial none = loadScene(file("zero.gltf", R"("KHR_materials_specular": {"specularColorFactor": [0, 0, 0]})")).materials[0];
    EXPECT_NEAR(none.rhoD.x, 0.8, 1e-6);
    EXPECT_NEAR(none.rhoD.z, 0.4, 1e-6);
    EXPECT_EQ(none.rhoS.x, 0.0);
    const PhongMaterial ior = loadScene(file("ior.gltf", R"("KHR_materials_ior": {"ior": 2.0}, "KHR_materials_specular": {"specularFactor": 0.5})"))
                                  .materials[0];
    const double f0 = 0.5 / 9;
    EXPECT_NEAR(ior.rhoS.y, f0, 1e-6);
    EXPECT_NEAR(ior.rhoD.y, 0.6 * (1 - f0), 1e-6);
}

// Collada by hand: a <lambert> effect is purely diffuse (Assimp 5.2 would give it its default specular 0.4
// and shininess 10), a <constant> one only emits, a <phong> one keeps its numbers. (The camera's <xfov>:
// BlenderExportsKeepTheCamerasFieldOfView, on Blender's own file.)
TEST(Assimp, ColladaShadingModels) {
    test::TempDir dir;
    const std::string dae = dir.write("s.dae", R"(<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><up_axis>Y_UP</up_axis></asset>
  <library_cameras><camera id="cam"><optics><technique_common><perspective>
    <xfov sid="xfov">39.3077</xfov><aspect_ratio>1.5</aspect_ratio><znear sid="znear">0.1</znear><zfar sid="zfar">100</zfar>
  </perspective></technique_common></optics></camera></library_cameras>
  <library_effects>
    <effect id="wall-fx"><profile_COMMON><technique sid="common"><lambert>
      <diffuse><color>0.8 0.2 0.1 1</color></diffuse></lambert></technique></profile_COMMON></effect>
    <effect id="lamp-fx"><profile_COMMON><technique sid="common"><constant>
      <emission><color>5 4 3 1</color></emission></constant></technique></profile_COMMON></effect>
    <effect id="gloss-fx"><profile_COMMON><technique sid="common"><phong>
      <diffuse><color>0.3 0.3 0.3 1</color></diffuse><specular><color>0.5 0.5 0.5 1</color></specular>
      <shininess><float>40</float></shininess></phong></technique></profile_COMMON></effect>
  </library_effects>
  <library_materials>
    <material id="wall"><instance_effect url="#wall-fx"/></material>
    <material id="lamp"><instance_effect url="#lamp-fx"/></material>
    <material id="gloss"><instance_effect url="#gloss-fx"/></material>
  </library_materials>
  <library_geometries><geometry id="g"><mesh>
    <source id="p"><float_array id="pa" count="9">0 0 0 1 0 0 0 1 0</float_array>
      <technique_common><accessor source="#pa" count="3" stride="3"><param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/></accessor></technique_common></source>
    <vertices id="v"><input semantic="POSITION" source="#p"/></vertices>
    <triangles material="wall" count="1"><input semantic="VERTEX" source="#v" offset="0"/><p>0 1 2</p></triangles>
    <triangles material="lamp" count="1"><input semantic="VERTEX" source="#v" offset="0"/><p>0 2 1</p></triangles>
    <triangles material="gloss" count="1"><input semantic="VERTEX" source="#v" offset="0"/><p>1 2 0</p></triangles>
  </mesh></geometry></library_geometries>
  <library_visual_scenes><visual_scene id="scene">
    <node id="mesh"><instance_geometry url="#g"><bind_material><technique_common>
      <instance_material symbol="wall" target="#wall"/><instance_material symbol="lamp" target="#lamp"/>
      <instance_material symbol="gloss" target="#gloss"/></technique_common></bind_material></instance_geometry></node>
    <node id="camera"><translate>0 0 5</translate><instance_camera url="#cam"/></node>
  </visual_scene></library_visual_scenes>
  <scene><instance_visual_scene url="#scene"/></scene>
</COLLADA>
)");
    const Scene s = loadScene(dae);
    const auto material = [&](const std::string& name) -> const PhongMaterial& {
        const int i = s.findMaterial(name);
        EXPECT_GE(i, 0) << name;
        return s.materials[static_cast<std::size_t>(std::max(i, 0))];
    };
    EXPECT_NEAR(material("wall").rhoD.x, 0.8, 1e-6);
    EXPECT_EQ(material("wall").rhoS.x, 0.0);
    EXPECT_EQ(material("lamp").rhoD.x, 0.0);
    EXPECT_EQ(material("lamp").rhoS.x, 0.0);
    EXPECT_NEAR(material("lamp").emission.x, 5.0, 1e-6);
    EXPECT_NEAR(material("gloss").rhoS.x, 0.5, 1e-6);
    EXPECT_NEAR(material("gloss").exponent, 40.0, 1e-4);
}

// FBX's SpecularFactor scales the specular colour (Assimp 5.2 hands it over apart, as the shininess
// strength): the test file with its factor set to 0.25, and to 0 (Blender's "Specular 0").
TEST(Assimp, FbxSpecularFactorScalesTheSpecularColour) {
    test::TempDir dir;
    std::string fbx = readTextFile(SYMPHONG_SOURCE_DIR "/tests/data/fbx/box.fbx");
    for (const double factor : {0.25, 0.0}) {
        std::string text = fbx;
        const std::string from = "P: \"SpecularFactor\", \"Number\", \"\", \"A\",1";
        for (std::size_t p = text.find(from); p != std::string::npos; p = text.find(from, p + 1))
            text.replace(p, from.size(), "P: \"SpecularFactor\", \"Number\", \"\", \"A\"," + std::to_string(factor));
        const std::string path = dir.write("box.fbx", text);
        const Scene s = loadScene(path);
        const int white = s.findMaterial("white");
        ASSERT_GE(white, 0);
        EXPECT_NEAR(s.materials[static_cast<std::size_t>(white)].rhoS.x, 0.2 * factor, 1e-6) << factor;
        EXPECT_NEAR(s.materials[static_cast<std::size_t>(white)].rhoD.x, 0.7, 1e-6) << factor;
    }
}

// The scene Blender 3.4 exported (tests/data/blender/, scripts/blender-roundtrip/make_scene.py): its camera
// (40 mm lens on a 36 mm sensor, 640 x 480) has a horizontal field of view of 2 atan(18 / 40) = 48.4555
// degrees, a vertical one of 2 atan(tan(24.2277 deg) / (4/3)) = 37.2991; glTF gives yfov, FBX and Collada the
// full horizontal angle, each of which must come out as that vertical one.
TEST(Assimp, BlenderExportsKeepTheCamerasFieldOfView) {
    const double horizontal = 2 * std::atan(18.0 / 40.0);
    const double vertical = 2 * std::atan(std::tan(horizontal / 2) / (640.0 / 480.0)) * 180 / kPi;
    EXPECT_NEAR(vertical, 37.2991, 1e-3);
    for (const char* file : {"scene.glb", "scene.gltf", "scene.fbx", "scene.dae"}) {
        const Scene s = loadScene(std::string(SYMPHONG_SOURCE_DIR) + "/tests/data/blender/" + file);
        EXPECT_NEAR(s.camera.fovY, vertical, 0.01) << file;
    }
}

// Glossy Principled materials that Blender 3.4 wrote (tests/data/blender/glossy/, scripts/blender-roundtrip/
// make_glossy.py), against the Phong parameters computed here by hand from the Principled numbers Blender was
// given (truth.json), not from what the files hold: Blender's FBX writes SpecularFactor = Specular / 2,
// ShininessExponent = ((1 - Roughness) 10)^2, ReflectionFactor = Metallic; its MTL Ks = Specular, Ns = (1 -
// Roughness)^2 1000. Undone, they must give F0 = 0.08 Specular, rho_s = F0 (1 - M) + base M, rho_d = base (1 -
// M) (1 - F0), n = 2 / alpha^2 - 2 with alpha = Roughness^2 (scene/exporter_conventions.h). Every material is
// glossy and each has another Specular, Roughness and Metallic, so a wrong factor in any of the three shows
// (the round trip's one glossy block, F0 0.04 in a diffusely lit box, renders within its tolerance either way).
// Blender's MTL carries no metallic (no Pm; 3.4.1 writes Ka and illum 3 instead), so the OBJ is checked on its
// two non-metallic materials only.
TEST(Assimp, BlenderGlossyMaterialsAreTheirPrincipledParameters) {
    const std::string dir = std::string(SYMPHONG_SOURCE_DIR) + "/tests/data/blender/glossy/";
    const nlohmann::json truth = nlohmann::json::parse(readTextFile(dir + "truth.json"));
    ASSERT_EQ(truth.at("blender").get<std::string>().substr(0, 3), "3.4");
    int checked = 0;
    for (const char* file : {"scene.fbx", "scene.obj"}) {
        const Scene s = loadScene(dir + file);
        for (const auto& [name, m] : truth.at("materials").items()) {
            const double metallic = m.at("metallic"), specular = m.at("specular"), roughness = m.at("roughness");
            if (std::string(file) == "scene.obj" && metallic != 0) continue;
            const int index = s.findMaterial(name);
            ASSERT_GE(index, 0) << file << " " << name;
            const PhongMaterial& got = s.materials[static_cast<std::size_t>(index)];
            const double f0 = 0.08 * specular, alpha = roughness * roughness;
            for (int c = 0; c < 3; ++c) {
                const double base = m.at("base_color").at(static_cast<std::size_t>(c));
                EXPECT_NEAR(got.rhoS[c], f0 * (1 - metallic) + base * metallic, 1e-5) << file << " " << name << " channel " << c;
                EXPECT_NEAR(got.rhoD[c], base * (1 - metallic) * (1 - f0), 1e-5) << file << " " << name << " channel " << c;
            }
            const double n = 2 / (alpha * alpha) - 2;
            EXPECT_NEAR(got.exponent, n, 1e-4 * n) << file << " " << name;
            ++checked;
        }
    }
    EXPECT_EQ(checked, 4 + 2);
}

TEST(Assimp, BadFilesAreBadInput) {
    test::TempDir dir;
    EXPECT_THROW(loadScene(dir.file("missing.glb")), MissingFileError);
    const std::string junk = dir.write("junk.glb", "this is not a glTF binary");
    try {
        loadScene(junk);
        ADD_FAILURE() << "accepted a junk .glb";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find(junk), std::string::npos) << e.what();
    }
    const std::string empty = dir.write(
        "empty.ply", "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\nproperty float z\nend_header\n");
    EXPECT_THROW(loadScene(empty), InputError);
    const std::string json = dir.write("bad.json", R"({"mesh": "model.xyz"})");
    try {
        loadScene(json);
        ADD_FAILURE() << "accepted a .xyz mesh";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("not a format symphong reads"), std::string::npos) << e.what();
    }
}

// tests/data/fbx/box.fbx, written by scripts/make-test-fbx.py (we cannot use Assimp's FBX exporter, above):
// an ASCII FBX 7.4 file, y up, UnitScaleFactor 100 (one unit = 1 m; Assimp 5.2 keeps the coordinates as
// written). A closed box from (0, 0, 0) to (2, 1, 3) of 6 quads wound outwards, with a normal per
// corner; the top (y = 1) quad of material "lamp" (EmissiveColor 5, diffuse and specular 0, exponent 1),
// the other five of "white" (DiffuseColor 0.7, SpecularColor 0.2, ShininessExponent 20), every *Factor 1.
// A camera at (1, 0.5, 10) turned 90 degrees about +y: an FBX camera looks along its node's +x, so it
// looks along -z at the box; FieldOfView 60 degrees, horizontal (ApertureMode 1), aspect 640 / 480. A
// point light at (1, 2.5, 1.5), Color (1, 0.9, 0.8), Intensity 250: FBX intensities are percentages,
// so Assimp gives (and symphong takes as the radiant intensity I) the colour x 2.5.
// The field of view: Assimp 5.2's FBX importer puts the file's full horizontal angle into
// aiCamera::mHorizontalFOV (whose comment says half of it; Assimp 5.3 halves it), so the vertical field of
// view is 2 atan(tan(60 deg / 2) / (4/3)) = 46.83 degrees, not the 104.8 degrees that reading 60 degrees
// as the half-angle gives.
TEST(Assimp, AuthoredFbxLoadsItsGeometryMaterialsCameraAndLight) {
    const Scene s = loadScene(std::string(SYMPHONG_SOURCE_DIR) + "/tests/data/fbx/box.fbx");
    ASSERT_EQ(s.triangles.size(), 12u) << "6 quads";
    Vec3 lo, hi;
    s.bounds(lo, hi);
    const Vec3 lo0(0, 0, 0), hi0(2, 1, 3);
    EXPECT_LT(length(lo - lo0) + length(hi - hi0), 1e-4 * length(hi0 - lo0)) << "the bounding box moved or was scaled";

    // Areas by material, and the lamp's winding: it emits on its counter-clockwise side, upwards.
    const auto materialNamed = [&](const std::string& name) -> const PhongMaterial* {
        for (const PhongMaterial& m : s.materials)
            if (m.name == name) return &m;
        return nullptr;
    };
    const PhongMaterial* white = materialNamed("white");
    const PhongMaterial* lamp = materialNamed("lamp");
    ASSERT_NE(white, nullptr);
    ASSERT_NE(lamp, nullptr);
    double area = 0, whiteArea = 0, lampArea = 0;
    int lampTriangles = 0;
    for (const Triangle& t : s.triangles) {
        const Vec3 c = cross(s.positions[t.v[1]] - s.positions[t.v[0]], s.positions[t.v[2]] - s.positions[t.v[0]]);
        area += 0.5 * length(c);
        const PhongMaterial& m = s.materials[t.material];
        if (&m == white) whiteArea += 0.5 * length(c);
        if (&m == lamp) {
            lampArea += 0.5 * length(c), ++lampTriangles;
            EXPECT_GT(normalize(c).y, 1 - 1e-9) << "the lamp's triangles face down";
        }
    }
    EXPECT_NEAR(area, 2 * (2 * 3 + 2 * 1 + 1 * 3), 1e-6 * 22);
    EXPECT_NEAR(lampArea, 2 * 3, 1e-6 * 6);
    EXPECT_NEAR(whiteArea, 22 - 6, 1e-6 * 16);
    EXPECT_EQ(lampTriangles, 2);

    // Phong / Blinn parameters directly: diffuse -> rho_d, specular -> rho_s, shininess -> n, emissive -> Le.
    for (const Color& c : {white->rhoD, white->rhoS, white->emission, lamp->rhoD, lamp->rhoS, lamp->emission}) {
        EXPECT_NEAR(c.x, c.y, 1e-9) << "grey in the file";
        EXPECT_NEAR(c.y, c.z, 1e-9) << "grey in the file";
    }
    EXPECT_NEAR(white->rhoD.x, 0.7, 1e-6);
    EXPECT_NEAR(white->rhoS.x, 0.2, 1e-6);
    EXPECT_NEAR(white->exponent, 20, 1e-5);
    EXPECT_EQ(white->emission.x, 0.0);
    EXPECT_EQ(lamp->rhoD.x, 0.0);
    EXPECT_EQ(lamp->rhoS.x, 0.0);
    EXPECT_NEAR(lamp->exponent, 1, 1e-6);
    EXPECT_NEAR(lamp->emission.x, 5, 1e-6);

    EXPECT_NEAR(s.camera.position.x, 1, 1e-5);
    EXPECT_NEAR(s.camera.position.y, 0.5, 1e-5);
    EXPECT_NEAR(s.camera.position.z, 10, 1e-5);
    const Vec3 view = normalize(s.camera.target - s.camera.position);
    EXPECT_GT(dot(view, Vec3(0, 0, -1)), 1 - 1e-9) << "the camera looks along -z (its node's +x turned about +y)";
    EXPECT_GT(dot(normalize(s.camera.up), Vec3(0, 1, 0)), 1 - 1e-9);
    EXPECT_NEAR(s.camera.fovY, 2 * std::atan(std::tan(30 * kPi / 180) / (640.0 / 480.0)) * 180 / kPi, 0.01)
        << "the vertical field of view of a 60-degree horizontal one at aspect 4/3";

    ASSERT_EQ(s.lights.size(), 1u);
    const Light& l = s.lights[0];
    EXPECT_EQ(l.type, Light::Type::Point);
    EXPECT_NEAR(l.position.x, 1, 1e-5);
    EXPECT_NEAR(l.position.y, 2.5, 1e-5);
    EXPECT_NEAR(l.position.z, 1.5, 1e-5);
    EXPECT_NEAR(l.intensity.x, 1.0 * 2.5, 1e-5);
    EXPECT_NEAR(l.intensity.y, 0.9 * 2.5, 1e-5);
    EXPECT_NEAR(l.intensity.z, 0.8 * 2.5, 1e-5);
}

// The authored FBX against its OBJ twin (the same box, materials and point light, written here): seen by
// one camera under one environment, the two render the same mean radiance within statistics.
TEST(Assimp, AuthoredFbxRendersTheMeanOfItsObjTwin) {
    test::TempDir dir;
    dir.write("twin.mtl", "newmtl white\nKd 0.7 0.7 0.7\nKs 0.2 0.2 0.2\nNs 20\nnewmtl lamp\nKd 0 0 0\nKs 0 0 0\nNs 1\nKe 5 5 5\n");
    // Box (0,0,0)-(2,1,3), faces wound outwards; the top is the lamp.
    dir.write("twin.obj",
              "mtllib twin.mtl\n"
              "v 0 0 0\nv 2 0 0\nv 2 1 0\nv 0 1 0\nv 0 0 3\nv 2 0 3\nv 2 1 3\nv 0 1 3\n"
              "usemtl white\nf 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 1 5 8 4\n"
              "usemtl lamp\nf 4 8 7 3\n");
    const std::string camera =
        R"("camera": {"position": [4.5, 3, 7], "target": [1, 0.5, 1.5], "up": [0, 1, 0], "fov": 40}, "environment": 0.3)";
    const std::string fbx = std::string(SYMPHONG_SOURCE_DIR) + "/tests/data/fbx/box.fbx";
    const Scene a = loadScene(dir.write("fbx.json", "{\"mesh\": \"" + fbx + "\", " + camera + "}"));
    const Scene b = loadScene(
        dir.write("obj.json", "{\"obj\": \"twin.obj\", " + camera +
                                  R"(, "lights": [{"type": "point", "position": [1, 2.5, 1.5], "intensity": [2.5, 2.25, 2.0]}]})"));
    ASSERT_EQ(a.lights.size(), 1u);
    const auto [ma, sa] = test::imageMeanAndError(renderSmall(a));
    const auto [mb, sb] = test::imageMeanAndError(renderSmall(b));
    EXPECT_NEAR(ma, mb, 4 * std::hypot(sa, sb)) << "se " << sa << ", " << sb;
    EXPECT_GT(mb, 0.3) << "the lamp and the lit box are in view";
}

namespace {

/// A glTF of one mesh whose primitives share `positions` and each have their own index list and mode
/// (4 triangles, 5 strip, 6 fan, 1 lines), the buffer in a file beside it; no material.
std::string writePrimitivesGltf(const test::TempDir& dir, const std::string& name, const std::vector<std::array<float, 3>>& positions,
                                const std::vector<std::pair<int, std::vector<std::uint16_t>>>& primitives) {
    std::string bin;
    for (const auto& p : positions) bin.append(reinterpret_cast<const char*>(p.data()), 12);
    std::string views = fmt::format(R"({{"buffer": 0, "byteOffset": 0, "byteLength": {}}})", bin.size());
    std::string accessors = fmt::format(R"({{"bufferView": 0, "componentType": 5126, "count": {}, "type": "VEC3"}})", positions.size());
    std::string prims;
    for (std::size_t k = 0; k < primitives.size(); ++k) {
        const auto& [mode, indices] = primitives[k];
        while (bin.size() % 4) bin.push_back('\0');
        views += fmt::format(R"(, {{"buffer": 0, "byteOffset": {}, "byteLength": {}}})", bin.size(), indices.size() * 2);
        for (std::uint16_t i : indices) bin.append(reinterpret_cast<const char*>(&i), 2);
        accessors += fmt::format(R"(, {{"bufferView": {}, "componentType": 5123, "count": {}, "type": "SCALAR"}})", k + 1, indices.size());
        prims += fmt::format(R"({}{{"attributes": {{"POSITION": 0}}, "indices": {}, "mode": {}}})", k ? ", " : "", k + 1, mode);
    }
    std::ofstream(dir.file(name + ".bin"), std::ios::binary) << bin;
    return dir.write(name + ".gltf", fmt::format(R"({{"asset": {{"version": "2.0"}}, "buffers": [{{"uri": "{}.bin", "byteLength": {}}}],
  "bufferViews": [{}], "accessors": [{}], "meshes": [{{"primitives": [{}]}}], "nodes": [{{"mesh": 0}}], "scenes": [{{"nodes": [0]}}], "scene": 0}})",
                                                 name, bin.size(), views, accessors, prims));
}

bool warnedWith(const Scene& s, const std::string& text) {
    return std::any_of(s.warnings.begin(), s.warnings.end(), [&](const std::string& w) { return w.find(text) != std::string::npos; });
}

}  // namespace

TEST(Assimp, WhatIsNotDrawnOrNotReadIsSaid) {
    test::TempDir dir;
    const std::vector<std::array<float, 3>> grid{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0, 2, 0}, {1, 2, 0}};
    // A strip of 6 indices (4 triangles), a fan of 5 (3), and two line segments: 7 triangles are drawn,
    // the lines are named, and the declared count (7) agrees with what Assimp read.
    const Scene mixed = loadScene(writePrimitivesGltf(dir, "mixed", grid, {{5, {0, 1, 2, 3, 4, 5}}, {6, {0, 1, 3, 5, 4}}, {1, {0, 1, 1, 3}}}));
    EXPECT_EQ(mixed.triangles.size(), 7u);
    EXPECT_TRUE(warnedWith(mixed, "0 points and 2 line segments are not drawn"));
    EXPECT_FALSE(warnedWith(mixed, "declare"));
    // A file without materials gets the neutral default (not Assimp's glTF stand-in, a rough white metal).
    ASSERT_EQ(mixed.materials.size(), 1u);
    EXPECT_EQ(mixed.materials[0].rhoD, Color(0.7));
    EXPECT_EQ(mixed.materials[0].rhoS, Color(0.0));
    // Three triangles declared, the third with a vertex index past the end: Assimp 5.2 drops it silently.
    const Scene dropped = loadScene(writePrimitivesGltf(dir, "dropped", grid, {{4, {0, 1, 2, 1, 3, 2, 1, 3, 99}}}));
    EXPECT_EQ(dropped.triangles.size(), 2u);
    EXPECT_TRUE(warnedWith(dropped, "declare 3 triangles, but Assimp")) << (dropped.warnings.empty() ? "" : dropped.warnings[0]);
}

// Loading while another thread allocates: the child that first reads a file (scene/assimp_guard.cpp) is forked
// while the other thread may hold the allocator's locks. glibc's allocator keeps them across fork(); GCC 12's
// AddressSanitizer does not, and its build read every file in a child that then waited forever on its first
// allocation (a Python test of the sanitizer build hung so): there it now reads in the process when the process
// has other threads. Twenty loads of Blender's FBX and glTF exports beside a thread that allocates and frees
// without pause: each loads, the same triangles each time (a hang is this test's failure, by CTest's timeout).
TEST(Assimp, LoadsWhileAnotherThreadAllocates) {
    std::atomic<bool> stop{false};
    std::thread churn([&] {
        std::vector<std::unique_ptr<char[]>> held(64);
        for (std::size_t i = 0; !stop.load(std::memory_order_relaxed); ++i) held[i % held.size()] = std::make_unique<char[]>(16 + i % 512);
    });
    for (int k = 0; k < 20; ++k) {
        const std::string file = SYMPHONG_SOURCE_DIR "/tests/data/blender/scene." + std::string(k % 2 ? "fbx" : "glb");
        const Scene s = loadScene(file);
        EXPECT_EQ(s.triangles.size(), loadScene(file).triangles.size()) << file;
        EXPECT_GT(s.triangles.size(), 0u) << file;
    }
    stop = true;
    churn.join();
}
