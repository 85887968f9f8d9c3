// scene/assimp_loader.cpp — mesh formats other than OBJ through Assimp (Debian's libassimp-dev): glTF 2.0,
// FBX, Collada, 3DS and the rest Assimp reads (PLY has its own reader, ply_loader.cpp), each first in a
// child process (assimp_guard.h). Meshes are triangulated and placed by their nodes'
// transforms (with the file's tangents where it has them); materials and their textures are mapped by
// scene/assimp_materials.h; the file's first camera and its point, spot and directional lights are kept.
// Coordinates stay as the file defines them (glTF: y up, metres). After the load, what the file holds
// that is not drawn (points, lines) and what Assimp read short of a glTF's declared triangles is said.
#include "scene/scene.h"

#include "scene/assimp_guard.h"
#include "scene/assimp_materials.h"
#include "scene/exporter_conventions.h"

#include "io/files.h"
#include "io/input_error.h"
#include "io/memory.h"
#include "scene/surface.h"

#include <nlohmann/json.hpp>

#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <assimp/version.h>
#include <fmt/format.h>
#include <assimp/Importer.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>

// Debian's Assimp 5.2 is built with its internal assertions on: a failed one calls
// Assimp::aiAssertViolation, which aborts the whole process (a malformed Collada <polylist> did; found
// by fuzzing, docs/reliability.md). This definition replaces the library's for the program (ELF symbol
// interposition: the executable's definition is found first) by one that throws; Assimp's ReadFile
// catches the exception and reports a failed import, which becomes an InputError below. (The Python
// module, loaded with local symbols, cannot replace it: there such a file still aborts.)
namespace Assimp {
void aiAssertViolation(const char* expression, const char* file, int line) {
    throw std::runtime_error(fmt::format("its internal check '{}' failed ({}:{})", expression, file, line));
}
}  // namespace Assimp

namespace symphong {

namespace {

/// Every node with its world transform, in depth-first pre-order, without recursion (a file may chain
/// thousands of nodes; the fuzzer found a 6000-deep glTF chain that overflowed a recursive walk).
std::vector<std::pair<const aiNode*, aiMatrix4x4>> worldTransforms(const aiNode* root) {
    std::vector<std::pair<const aiNode*, aiMatrix4x4>> out, stack{{root, root->mTransformation}};
    while (!stack.empty()) {
        const auto [node, world] = stack.back();
        stack.pop_back();
        out.emplace_back(node, world);
        for (unsigned i = node->mNumChildren; i-- > 0;) stack.emplace_back(node->mChildren[i], world * node->mChildren[i]->mTransformation);
    }
    return out;
}

/// The world transform of every node, by name (cameras and lights are placed by the node of their name).
std::vector<std::pair<std::string, aiMatrix4x4>> namedTransforms(const std::vector<std::pair<const aiNode*, aiMatrix4x4>>& nodes) {
    std::vector<std::pair<std::string, aiMatrix4x4>> out;
    out.reserve(nodes.size());
    for (const auto& [node, world] : nodes) out.emplace_back(node->mName.C_Str(), world);
    return out;
}

aiMatrix4x4 nodeTransform(const std::vector<std::pair<std::string, aiMatrix4x4>>& nodes, const aiString& name) {
    for (const auto& [n, m] : nodes)
        if (n == name.C_Str()) return m;
    return aiMatrix4x4();
}

/// The JSON of a .gltf file or of a .glb's JSON chunk; null for other files. A .gltf that is not JSON
/// (glTF is UTF-8 JSON) or a .glb without a glTF header and JSON chunk is refused here: Assimp 5.2 would
/// hand it to every other importer by signature, some of which crash or ask for terabytes on such input
/// (docs/reliability.md). Assimp 5.2 drops two things that we read here: a material's
/// KHR_materials_emissive_strength, and a camera's exact vertical field of view (it gives yfov x
/// aspect as the horizontal one).
nlohmann::json gltfJson(const std::string& path) {
    const std::string ext = lowerExtension(path);
    if (ext != ".gltf" && ext != ".glb") return nullptr;
    const std::string bytes = readTextFile(path);
    std::string text = bytes;
    if (ext == ".glb") {
        // Header: magic, version, length; then chunk 0: its length and type ("JSON"), then its bytes.
        if (bytes.size() < 20 || bytes.compare(0, 4, "glTF") != 0 || bytes.compare(16, 4, "JSON") != 0)
            throw InputError(fmt::format("{}: not a glTF binary (no 'glTF' header followed by a JSON chunk)", path));
        std::uint32_t length = 0;
        std::memcpy(&length, bytes.data() + 12, 4);
        if (length > bytes.size() - 20)
            throw InputError(fmt::format("{}: the glTF binary's JSON chunk runs past the end of the file", path));
        text = bytes.substr(20, length);
    }
    nlohmann::json doc = nlohmann::json::parse(text, nullptr, false);
    if (doc.is_discarded()) throw InputError(fmt::format("{}: not a glTF file (its JSON is malformed or not UTF-8)", path));
    return doc;
}

/// Checks what Assimp 5.2's glTF 2 importer does not before it reads through it: every mesh primitive
/// has a POSITION accessor, and its attribute and index accessors exist (a line-loop primitive without
/// POSITION made the importer crash; found by fuzzing, docs/reliability.md).
void checkGltfPrimitives(const nlohmann::json& gltf, const std::string& path) {
    if (!gltf.is_object() || !gltf.contains("meshes") || !gltf["meshes"].is_array()) return;
    const std::size_t accessors = gltf.contains("accessors") && gltf["accessors"].is_array() ? gltf["accessors"].size() : 0;
    const auto validAccessor = [&](const nlohmann::json& a) { return a.is_number_unsigned() && a.get<std::uint64_t>() < accessors; };
    const nlohmann::json& meshes = gltf["meshes"];
    for (std::size_t m = 0; m < meshes.size(); ++m) {
        if (!meshes[m].is_object() || !meshes[m].contains("primitives") || !meshes[m]["primitives"].is_array()) continue;
        const nlohmann::json& primitives = meshes[m]["primitives"];
        for (std::size_t p = 0; p < primitives.size(); ++p) {
            const nlohmann::json& prim = primitives[p];
            const std::string where = fmt::format("{}: meshes[{}].primitives[{}]", path, m, p);
            if (!prim.is_object() || !prim.contains("attributes") || !prim["attributes"].is_object() ||
                !prim["attributes"].contains("POSITION"))
                throw InputError(fmt::format("{} has no POSITION attribute", where));
            for (const auto& item : prim["attributes"].items())
                if (!validAccessor(item.value()))
                    throw InputError(fmt::format("{}.attributes.{} is not an accessor of the file", where, item.key()));
            if (prim.contains("indices") && !validAccessor(prim["indices"]))
                throw InputError(fmt::format("{}.indices is not an accessor of the file", where));
        }
    }
}

}  // namespace

namespace {

/// One triangle mesh placed by its node's world transform (normals by its inverse transpose).
void addMesh(const aiMesh* mesh, const aiMatrix4x4& world, const aiMatrix3x3& normalMatrix, const std::string& path, Scene& scene) {
    const auto base = static_cast<std::uint32_t>(scene.positions.size());
    const auto normalBase = static_cast<std::int32_t>(scene.normals.size());
    const auto uvBase = static_cast<std::int32_t>(scene.uvs.size());
    const bool hasUvs = mesh->mTextureCoords[0] != nullptr;
    // Tangents only where the file gave them (no aiProcess_CalcTangentSpace): glTF's TANGENT, whose
    // bitangent Assimp makes cross(n, t) w; placed by the node's transform, the sign read back after it.
    const bool hasTangents = mesh->mNormals && mesh->mTangents && mesh->mBitangents;
    const auto tangentBase = static_cast<std::int32_t>(scene.tangents.size());
    const aiMatrix3x3 linear(world);
    requireMemory(saturatingMultiply(mesh->mNumVertices, 80) + saturatingMultiply(mesh->mNumFaces, 48),
                  fmt::format("{}: mesh '{}' of {} vertices and {} faces", path, mesh->mName.C_Str(), mesh->mNumVertices, mesh->mNumFaces));
    for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
        const Vec3 p = toVec3(world * mesh->mVertices[v]);
        if (!isFinite(p)) throw InputError(fmt::format("{}: mesh '{}' vertex {} is not finite", path, mesh->mName.C_Str(), v));
        scene.positions.push_back(p);
        if (mesh->mNormals) {
            Vec3 n = toVec3(normalMatrix * mesh->mNormals[v]);
            const double len = length(n);
            scene.normals.push_back(len > 0 && std::isfinite(len) ? n / len : Vec3(0, 1, 0));
        }
        if (hasTangents) {
            const Vec3 t = toVec3(linear * mesh->mTangents[v]), b = toVec3(linear * mesh->mBitangents[v]);
            const double len = length(t);
            const bool usable = len > 0 && std::isfinite(len) && isFinite(b);
            scene.tangents.push_back({usable ? t / len : Vec3(1, 0, 0), usable && dot(cross(scene.normals.back(), t), b) < 0 ? -1.0 : 1.0});
        }
        if (hasUvs) {
            const aiVector3D& t = mesh->mTextureCoords[0][v];
            const bool finite = std::isfinite(t.x) && std::isfinite(t.y);
            scene.uvs.push_back({finite ? t.x : 0.0, finite ? t.y : 0.0});
        }
    }
    const std::uint32_t material = mesh->mMaterialIndex < scene.materials.size() ? mesh->mMaterialIndex : 0;
    for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
        const aiFace& face = mesh->mFaces[f];
        if (face.mNumIndices != 3) continue;
        Triangle t;
        t.material = material;
        for (int c = 0; c < 3; ++c) {
            const unsigned idx = face.mIndices[c];
            if (idx >= mesh->mNumVertices)
                throw InputError(fmt::format("{}: mesh '{}' face {} has a vertex index out of range", path, mesh->mName.C_Str(), f));
            t.v[static_cast<std::size_t>(c)] = base + idx;
            t.n[static_cast<std::size_t>(c)] = mesh->mNormals ? normalBase + static_cast<std::int32_t>(idx) : -1;
            t.t[static_cast<std::size_t>(c)] = hasUvs ? uvBase + static_cast<std::int32_t>(idx) : -1;
            t.tg[static_cast<std::size_t>(c)] = hasTangents ? tangentBase + static_cast<std::int32_t>(idx) : -1;
        }
        scene.triangles.push_back(t);
    }
}

/// Triangles a glTF file declares in its meshes (each mesh once, however many nodes place it): per
/// primitive, from its index count (or its POSITION count without indices): mode 4 (the default) count / 3,
/// strips and fans (5, 6) count - 2; -1 when some primitive's count cannot be read.
std::int64_t gltfDeclaredTriangles(const nlohmann::json& gltf) {
    std::int64_t total = 0;
    const nlohmann::json meshes = member(gltf, "/meshes");
    if (!meshes.is_array()) return 0;
    for (const nlohmann::json& mesh : meshes) {
        const nlohmann::json primitives = member(mesh, "/primitives");
        if (!primitives.is_array()) continue;
        for (const nlohmann::json& prim : primitives) {
            const double mode = number(prim, "/mode", 4);
            if (mode < 4) continue;  // points and lines: counted by checkWhatWasRead from what Assimp read
            const nlohmann::json accessor = prim.contains("indices") ? prim["indices"] : member(prim, "/attributes/POSITION");
            if (!accessor.is_number_unsigned()) return -1;
            const double count = number(gltf, fmt::format("/accessors/{}/count", accessor.get<std::uint64_t>()), -1);
            if (count < 0) return -1;
            total += mode == 4 ? static_cast<std::int64_t>(count) / 3 : std::max<std::int64_t>(0, static_cast<std::int64_t>(count) - 2);
        }
    }
    return total;
}

/// Says what the file holds that is not rendered, and where Assimp read less than the file declares:
/// points and line segments (symphong draws triangles); for glTF, the triangles its meshes declare
/// against those Assimp read (a mesh compressed with an extension Assimp 5.2 cannot decode, say).
void checkWhatWasRead(const aiScene& ai, const nlohmann::json& gltf, const std::string& path, Scene& scene) {
    std::uint64_t points = 0, lines = 0, triangles = 0;
    for (unsigned i = 0; i < ai.mNumMeshes; ++i)
        for (unsigned f = 0; f < ai.mMeshes[i]->mNumFaces; ++f) {
            const unsigned n = ai.mMeshes[i]->mFaces[f].mNumIndices;
            (n == 1 ? points : n == 2 ? lines : triangles) += 1;
        }
    if (points + lines > 0)
        scene.warnings.push_back(
            fmt::format("{}: {} points and {} line segments are not drawn (symphong renders triangles only)", path, points, lines));
    if (!gltf.is_object()) return;
    const std::int64_t declared = gltfDeclaredTriangles(gltf);
    if (declared >= 0 && static_cast<std::uint64_t>(declared) != triangles)
        scene.warnings.push_back(
            fmt::format("{}: the file's meshes declare {} triangles, but Assimp {} read {}: part of the geometry "
                        "is missing from the render",
                        path, declared, assimpVersion(), triangles));
}

/// The file's first camera, placed by its node (`blender`: Blender wrote the file, whose FBX and Collada angles lie along
/// the longer side of the picture).
Camera fileCamera(const aiScene& ai, const std::vector<std::pair<std::string, aiMatrix4x4>>& nodes, const nlohmann::json& gltf,
                  const std::string& path, bool blender) {
    const bool fbx = lowerExtension(path) == ".fbx";
    Camera camera;
    const aiCamera& c = *ai.mCameras[0];
    const aiMatrix4x4 world = nodeTransform(nodes, c.mName);
    aiMatrix3x3 rotation(world);
    const nlohmann::json yfov = member(gltf, "/cameras/0/perspective/yfov");
    if (yfov.is_number()) {
        // glTF: the camera sits at its node's origin looking down the node's -z, +y up (Assimp 5.2 also
        // copies the node's translation into the camera's position, which would count it twice).
        camera.position = toVec3(world * aiVector3D(0, 0, 0));
        camera.target = camera.position + normalize(toVec3(rotation * aiVector3D(0, 0, -1)));
        camera.up = normalize(toVec3(rotation * aiVector3D(0, 1, 0)));
        camera.fovY = yfov.get<double>() * 180.0 / kPi;
        return camera;
    }
    const Vec3 position = toVec3(world * c.mPosition);
    camera.position = position;
    camera.target = position + normalize(toVec3(rotation * c.mLookAt));
    camera.up = normalize(toVec3(rotation * c.mUp));
    // aiCamera::mHorizontalFOV is documented as half the horizontal field of view, but Assimp 5.2's FBX
    // importer stores the file's full FieldOfView there (Assimp 5.3 halves it), and its Collada importer
    // the full <xfov> (or the full angle it computes from <yfov> and <aspect_ratio>). The vertical field
    // of view follows from the half-angle and the aspect ratio.
    const double aspect = c.mAspect > 0 ? c.mAspect : 1.0;
    const bool dae = lowerExtension(path) == ".dae";
    double half = c.mHorizontalFOV;
    if (fbx && (aiGetVersionMajor() < 5 || (aiGetVersionMajor() == 5 && aiGetVersionMinor() < 3))) half *= 0.5;
    if (dae) half *= 0.5;
    // Blender writes the angle along the longer side (scene/exporter_conventions.h): the vertical one of
    // a portrait picture.
    const bool blenderPortrait = aspect < 1 && blender && (fbx || dae);
    camera.fovY = (blenderPortrait ? 2.0 * half : 2.0 * std::atan(std::tan(half) / aspect)) * 180.0 / kPi;
    return camera;
}

/// One of the file's lights, placed by its node; a kind symphong does not have is a warning.
void addLight(const aiLight& l, const std::vector<std::pair<std::string, aiMatrix4x4>>& nodes, const std::string& path, Scene& scene) {
    const aiMatrix4x4 world = nodeTransform(nodes, l.mName);
    aiMatrix3x3 rotation(world);
    Light light;
    light.intensity = toColor(l.mColorDiffuse);
    light.position = toVec3(world * l.mPosition);
    light.direction = toVec3(rotation * l.mDirection);
    if (length(light.direction) == 0) light.direction = Vec3(0, -1, 0);
    light.direction = normalize(light.direction);
    switch (l.mType) {
        case aiLightSource_POINT:
            light.type = Light::Type::Point;
            break;
        case aiLightSource_DIRECTIONAL:
            light.type = Light::Type::Directional;
            break;
        case aiLightSource_SPOT:
            // Half-angles from the axis, as glTF gives them.
            light.type = Light::Type::Spot;
            light.cosOuter = std::cos(std::clamp(static_cast<double>(l.mAngleOuterCone), 1e-3, kPi / 2));
            light.cosInner = std::min(std::cos(std::clamp(static_cast<double>(l.mAngleInnerCone), 0.0, kPi / 2)), 1.0);
            if (!(light.cosInner > light.cosOuter)) light.cosInner = std::min(1.0, light.cosOuter + 1e-3);
            break;
        default:
            scene.warnings.push_back(
                fmt::format("{}: light '{}' is of a kind symphong does not have (area/ambient); ignored", path, l.mName.C_Str()));
            return;
    }
    if (isFinite(light.intensity) && minComponent(light.intensity) >= 0) scene.lights.push_back(light);
}

}  // namespace

Scene loadAssimp(const std::string& path) {
    if (!std::filesystem::exists(path)) throw MissingFileError(fmt::format("{}: no such file", path));
    const nlohmann::json gltf = gltfJson(path);
    checkGltfPrimitives(gltf, path);
    checkAssimpInChild(path);  // a crash or runaway allocation inside Assimp is an InputError
    Assimp::Importer importer;
    const aiScene* ai = importWithAssimp(importer, path);
    if (!ai) throw InputError(fmt::format("{}: cannot read it (Assimp: {})", path, importer.GetErrorString()));

    Scene scene;
    scene.name = std::filesystem::path(path).stem().string();
    TextureTable table(scene);
    // Whether Blender wrote the file (its FBX material numbers and its FBX/Collada camera angles).
    const std::string ext = lowerExtension(path);
    const bool blender = (ext == ".fbx" && fbxWrittenByBlender(path)) || (ext == ".dae" && colladaWrittenByBlender(path));
    // Geometry without a material gets the neutral default of an OBJ without MTL (docs/scene-format.md):
    // Assimp's own stand-in (its "DefaultMaterial", or for glTF the material it appends after the file's
    // own, which has glTF's defaults: a rough white metal) is not what the file's author saw.
    const nlohmann::json gltfMaterials = member(gltf, "/materials");
    const std::size_t fileMaterials = gltfMaterials.is_array() ? gltfMaterials.size() : 0;
    for (unsigned i = 0; i < ai->mNumMaterials; ++i) {
        aiString name;
        const bool standIn = gltf.is_object() ? i >= fileMaterials
                                              : ai->mMaterials[i]->Get(AI_MATKEY_NAME, name) == AI_SUCCESS &&
                                                    std::string(name.C_Str()) == AI_DEFAULT_MATERIAL_NAME;
        scene.materials.push_back(
            standIn ? PhongMaterial{}
                    : mapMaterial(*ai, *ai->mMaterials[i], i, member(gltf, fmt::format("/materials/{}", i)), blender, table, scene, path));
    }
    if (scene.materials.empty()) scene.materials.push_back(PhongMaterial{});

    const std::vector<std::pair<const aiNode*, aiMatrix4x4>> placed = worldTransforms(ai->mRootNode);
    const std::vector<std::pair<std::string, aiMatrix4x4>> nodes = namedTransforms(placed);
    for (const auto& [node, world] : placed) {
        aiMatrix3x3 normalMatrix(world);
        normalMatrix.Inverse().Transpose();
        for (unsigned k = 0; k < node->mNumMeshes; ++k) {
            const aiMesh* mesh = ai->mMeshes[node->mMeshes[k]];
            if (mesh->mPrimitiveTypes & aiPrimitiveType_TRIANGLE) addMesh(mesh, world, normalMatrix, path, scene);
        }
    }
    if (scene.triangles.empty()) throw InputError(fmt::format("{}: no triangles in the file", path));
    checkWhatWasRead(*ai, gltf, path, scene);
    scene.camera = ai->mNumCameras > 0 ? fileCamera(*ai, nodes, gltf, path, blender) : scene.automaticCamera();
    for (unsigned i = 0; i < ai->mNumLights; ++i) addLight(*ai->mLights[i], nodes, path, scene);
    return scene;
}

std::string assimpVersion() { return fmt::format("{}.{}.{}", aiGetVersionMajor(), aiGetVersionMinor(), aiGetVersionPatch()); }

}  // namespace symphong
