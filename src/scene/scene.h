// scene/ — what is rendered: triangles with Phong materials, emitters, a camera and an environment
// radiance. Owns the built-in Cornell box and the loaders for Wavefront OBJ/MTL (through tinyobjloader)
// and JSON scene files (through nlohmann-json); validates every number it reads, so the layers below
// never see a NaN, a negative albedo or an out-of-range index. Textures on materials and the lookups that
// turn them into Phong parameters at a point are in scene/surface.h, normal and bump maps in
// scene/shading_normal.h with their tangent frames in scene/tangents.h; lat-long environment maps and
// their importance sampling in scene/environment_map.h.
#pragma once

#include "materials/phong.h"
#include "math/vec3.h"
#include "scene/environment_map.h"
#include "scene/light.h"
#include "scene/sky.h"
#include "texture/texture.h"

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace symphong {

struct Camera {
    Vec3 position{0, 0, 1};
    Vec3 target{0, 0, 0};
    Vec3 up{0, 1, 0};
    double fovY = 40.0;  ///< vertical field of view in degrees
};

struct Triangle {
    std::array<std::uint32_t, 3> v{};            ///< indices into Scene::positions
    std::array<std::int32_t, 3> n{-1, -1, -1};   ///< indices into Scene::normals, -1 when absent
    std::uint32_t material = 0;
    std::array<std::int32_t, 3> t{-1, -1, -1};   ///< indices into Scene::uvs, -1 when absent
    std::array<std::int32_t, 3> tg{-1, -1, -1};  ///< indices into Scene::tangents, -1 when absent
};

/// A vertex's tangent frame for normal maps: the unit tangent along increasing u, and the sign that
/// makes sign x cross(n, tangent) the bitangent along increasing v (-1 where the texture is mirrored).
struct Tangent {
    Vec3 t{1, 0, 0};
    double sign = 1;
};

struct Scene {
    std::string name = "scene";
    std::vector<Vec3> positions;
    std::vector<Vec3> normals;               ///< optional smoothing normals (unit length)
    std::vector<std::array<double, 2>> uvs;  ///< optional texture coordinates (u right, v up)
    std::vector<Tangent> tangents;           ///< tangent frames for normal and bump maps (from the file, or scene/tangents.h)
    std::vector<Triangle> triangles;
    std::vector<PhongMaterial> materials;
    std::vector<Texture> textures;  ///< what the materials' TextureRefs index
    std::vector<Light> lights;      ///< point, spot and directional lights (emissive triangles are materials)
    Camera camera;
    Color environment{0.0};                        ///< radiance arriving from directions that leave the scene
    std::optional<Sky> sky;                        ///< when set, rays that leave the scene see the sky instead of `environment`
    std::optional<EnvironmentMap> environmentMap;  ///< when set, they see this image (and it is light-sampled)
    std::vector<std::string> warnings;
    /// A JSON scene's "render" object, as text: the render settings the scene asks for, applied by the
    /// front ends through the render settings' schema (render/settings.h) under what the user gives.
    std::string renderSettings;

    /// Axis-aligned bounds of the positions.
    void bounds(Vec3& lo, Vec3& hi) const;
    /// Index of the material with this name, or -1.
    int findMaterial(const std::string& name) const;
    /// Whether anything emits: an emissive material on a triangle, a light, or an environment map that is not black.
    bool hasEmitter() const;
    /// A camera for a scene that gives none, framing its bounding sphere: a mesh with emissive triangles
    /// is a set with its own light fixtures (a Cornell box, open towards +Z by convention) and is seen
    /// from the +Z side; any other from a three-quarter view (from +X+Z, 20 degrees above), +Y up.
    Camera automaticCamera(double fovY = 40.0) const;
    /// Radiance arriving along unit direction d from outside the scene.
    Color environmentRadiance(const Vec3& d) const {
        if (environmentMap) return environmentMap->radiance(d);
        return sky ? skyRadiance(*sky, d) : environment;
    }
    /// Whether some material has a cut-out (alpha) texture.
    bool hasCutOuts() const;
};

/// The built-in Cornell box: the original Cornell geometry (0..556 units, the 130 x 105 light just
/// under the ceiling), red left wall, green right wall, and a glossy Phong tall block.
Scene makeCornellBox();

/// Loads a scene from a spec: "cornell" (built-in), a path ending in .obj, .json, or one of Assimp's
/// formats (.gltf, .glb, .ply, .fbx, .dae, .3ds).
/// Throws InputError on every problem; collects non-fatal notes in Scene::warnings.
Scene loadScene(const std::string& spec);

/// Wavefront OBJ with its MTL. Validates the file line by line before handing it to tinyobjloader.
Scene loadObj(const std::string& path);

/// A mesh file in a format other than OBJ, read through Assimp: glTF 2.0 (.gltf, .glb), PLY, FBX,
/// Collada (.dae), 3DS (scene/assimp_loader.cpp). Its first camera and its lights are kept.
Scene loadAssimp(const std::string& path);

/// A PLY file (ASCII or binary; faces and triangle strips) by our own reader (scene/ply_loader.cpp):
/// Assimp 5.2 reads one triangle of a mesh stored as strips.
Scene loadPly(const std::string& path);
/// Whether a file name's extension is one loadScene reads through Assimp.
bool isAssimpExtension(const std::string& path);
/// Whether it is a mesh file of any format (.obj, .ply, or one read through Assimp).
bool isMeshExtension(const std::string& path);
/// A mesh file by its extension (loadObj, loadPly or loadAssimp), without finalizeScene.
Scene loadMeshFile(const std::string& path);

/// JSON scene file; see docs/scene-format.md.
Scene loadJsonScene(const std::string& path);

/// Final checks shared by every loader: materials valid and energy conserving (clamped with a
/// warning), at least one triangle, a usable camera; adds the fallback environment when nothing emits.
void finalizeScene(Scene& scene, const std::string& source, bool environmentGiven);

/// The version of Assimp in use (the library's own, at run time).
std::string assimpVersion();

}  // namespace symphong
