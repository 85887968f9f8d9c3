// scene/assimp_loader.cpp — mesh formats other than OBJ through Assimp (Debian's libassimp-dev): glTF 2.0,
// PLY, FBX, Collada, 3DS and the rest Assimp reads. Meshes are triangulated and placed by their nodes'
// transforms; materials are mapped to Phong parameters by the table in docs/scene-format.md; the
// file's first camera and its point, spot and directional lights are kept. Coordinates stay as the
// file defines them (glTF: y up, metres).
#include "scene/scene.h"

#include "io/input_error.h"

#include <nlohmann/json.hpp>

#include <assimp/Importer.hpp>
#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>

namespace symphong {

namespace {

Vec3 toVec3(const aiVector3D& v) { return {v.x, v.y, v.z}; }
Color toColor(const aiColor3D& c) { return {c.r, c.g, c.b}; }

/// The world transform of every node, by name (cameras and lights are placed by the node of their name).
void collectTransforms(const aiNode* node, const aiMatrix4x4& parent, std::vector<std::pair<std::string, aiMatrix4x4>>& out) {
    const aiMatrix4x4 world = parent * node->mTransformation;
    out.emplace_back(node->mName.C_Str(), world);
    for (unsigned i = 0; i < node->mNumChildren; ++i) collectTransforms(node->mChildren[i], world, out);
}

aiMatrix4x4 nodeTransform(const std::vector<std::pair<std::string, aiMatrix4x4>>& nodes, const aiString& name) {
    for (const auto& [n, m] : nodes)
        if (n == name.C_Str()) return m;
    return aiMatrix4x4();
}

/// One material: Phong/Blinn parameters directly (diffuse -> rho_d, specular -> rho_s, shininess -> n,
/// emissive -> Le); a glTF metallic-roughness material by the stated approximation: rho_d = base (1 -
/// metallic), rho_s = 0.04 (1 - metallic) + base metallic, n = 2 / alpha^2 - 2 with alpha = roughness^2
/// (at most 10^4); emission times KHR_materials_emissive_strength.
PhongMaterial mapMaterial(const aiMaterial& m, std::size_t index) {
    PhongMaterial out;
    aiString name;
    out.name = m.Get(AI_MATKEY_NAME, name) == AI_SUCCESS && name.length > 0 ? name.C_Str() : fmt::format("material{}", index);
    aiColor4D base;
    float metallic = 0, roughness = 1;
    const bool pbr = m.Get(AI_MATKEY_BASE_COLOR, base) == AI_SUCCESS && m.Get(AI_MATKEY_METALLIC_FACTOR, metallic) == AI_SUCCESS;
    if (pbr) {
        m.Get(AI_MATKEY_ROUGHNESS_FACTOR, roughness);
        const Color b(base.r, base.g, base.b);
        out.rhoD = b * (1.0 - metallic);
        out.rhoS = Color(0.04 * (1.0 - metallic)) + b * metallic;
        const double alpha = std::max(1e-3, static_cast<double>(roughness) * roughness);
        out.exponent = std::clamp(2.0 / (alpha * alpha) - 2.0, 0.0, 1e4);
    } else {
        aiColor3D c;
        if (m.Get(AI_MATKEY_COLOR_DIFFUSE, c) == AI_SUCCESS) out.rhoD = toColor(c);
        if (m.Get(AI_MATKEY_COLOR_SPECULAR, c) == AI_SUCCESS) out.rhoS = toColor(c);
        float shininess = 0;
        if (m.Get(AI_MATKEY_SHININESS, shininess) == AI_SUCCESS) out.exponent = std::max(0.0f, shininess);
        if (isBlack(out.rhoS)) out.exponent = std::max(out.exponent, 1.0);
    }
    aiColor3D e;
    if (m.Get(AI_MATKEY_COLOR_EMISSIVE, e) == AI_SUCCESS) out.emission = toColor(e);
    float strength = 1;
    if (m.Get(AI_MATKEY_EMISSIVE_INTENSITY, strength) == AI_SUCCESS && strength != 1.0f) out.emission *= static_cast<double>(strength);
    return out;
}

/// The JSON of a .gltf file or of a .glb's JSON chunk; null for other files or when it cannot be read
/// (Assimp then reports the problem). Assimp 5.2 drops two things that we read here: a material's
/// KHR_materials_emissive_strength, and a camera's exact vertical field of view (it gives yfov x
/// aspect as the horizontal one).
nlohmann::json gltfJson(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    for (char& ch : ext) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
    if (ext != ".gltf" && ext != ".glb") return nullptr;
    std::ifstream in(path, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::string text = bytes;
    if (ext == ".glb") {
        // Header: magic, version, length; then chunk 0: its length and type ("JSON"), then its bytes.
        if (bytes.size() < 20 || bytes.compare(0, 4, "glTF") != 0 || bytes.compare(16, 4, "JSON") != 0) return nullptr;
        std::uint32_t length = 0;
        std::memcpy(&length, bytes.data() + 12, 4);
        if (length > bytes.size() - 20) return nullptr;
        text = bytes.substr(20, length);
    }
    return nlohmann::json::parse(text, nullptr, false);
}

/// The value at a JSON pointer, or null when any step of it is missing or of another type.
nlohmann::json member(const nlohmann::json& j, const std::string& pointer) {
    try {
        const nlohmann::json::json_pointer p(pointer);
        return j.is_object() && j.contains(p) ? j.at(p) : nlohmann::json();
    } catch (const nlohmann::json::exception&) {
        return nullptr;
    }
}

}  // namespace

Scene loadAssimp(const std::string& path) {
    if (!std::filesystem::exists(path)) throw MissingFileError(fmt::format("{}: no such file", path));
    Assimp::Importer importer;
    importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE, aiPrimitiveType_POINT | aiPrimitiveType_LINE);
    const aiScene* ai = importer.ReadFile(path, aiProcess_Triangulate | aiProcess_SortByPType | aiProcess_JoinIdenticalVertices |
                                                    aiProcess_ValidateDataStructure | aiProcess_FindInvalidData);
    if (!ai || !ai->mRootNode || (ai->mFlags & AI_SCENE_FLAGS_INCOMPLETE))
        throw InputError(fmt::format("{}: cannot read it (Assimp: {})", path, importer.GetErrorString()));

    Scene scene;
    scene.name = std::filesystem::path(path).stem().string();
    for (unsigned i = 0; i < ai->mNumMaterials; ++i) scene.materials.push_back(mapMaterial(*ai->mMaterials[i], i));
    if (scene.materials.empty()) scene.materials.push_back(PhongMaterial{});
    const nlohmann::json gltf = gltfJson(path);
    if (gltf.is_object() && gltf.contains("materials") && gltf["materials"].is_array())
        for (std::size_t i = 0; i < gltf["materials"].size() && i < scene.materials.size(); ++i) {
            const nlohmann::json strength = member(gltf, fmt::format("/materials/{}/extensions/KHR_materials_emissive_strength/emissiveStrength", i));
            if (strength.is_number() && std::isfinite(strength.get<double>()) && strength.get<double>() >= 0)
                scene.materials[i].emission *= strength.get<double>();
        }

    std::vector<std::pair<std::string, aiMatrix4x4>> nodes;
    collectTransforms(ai->mRootNode, aiMatrix4x4(), nodes);
    // Every node's meshes, placed by the node's world transform; normals by its inverse transpose.
    const std::function<void(const aiNode*, const aiMatrix4x4&)> place = [&](const aiNode* node, const aiMatrix4x4& parent) {
        const aiMatrix4x4 world = parent * node->mTransformation;
        aiMatrix3x3 normalMatrix(world);
        normalMatrix.Inverse().Transpose();
        for (unsigned k = 0; k < node->mNumMeshes; ++k) {
            const aiMesh* mesh = ai->mMeshes[node->mMeshes[k]];
            if (!(mesh->mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) continue;
            const auto base = static_cast<std::uint32_t>(scene.positions.size());
            const auto normalBase = static_cast<std::int32_t>(scene.normals.size());
            for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
                const Vec3 p = toVec3(world * mesh->mVertices[v]);
                if (!isFinite(p)) throw InputError(fmt::format("{}: mesh '{}' vertex {} is not finite", path, mesh->mName.C_Str(), v));
                scene.positions.push_back(p);
                if (mesh->mNormals) {
                    Vec3 n = toVec3(normalMatrix * mesh->mNormals[v]);
                    const double len = length(n);
                    scene.normals.push_back(len > 0 && std::isfinite(len) ? n / len : Vec3(0, 1, 0));
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
                    if (idx >= mesh->mNumVertices) throw InputError(fmt::format("{}: mesh '{}' face {} has a vertex index out of range", path, mesh->mName.C_Str(), f));
                    t.v[static_cast<std::size_t>(c)] = base + idx;
                    t.n[static_cast<std::size_t>(c)] = mesh->mNormals ? normalBase + static_cast<std::int32_t>(idx) : -1;
                }
                scene.triangles.push_back(t);
            }
        }
        for (unsigned i = 0; i < node->mNumChildren; ++i) place(node->mChildren[i], world);
    };
    place(ai->mRootNode, aiMatrix4x4());
    if (scene.triangles.empty()) throw InputError(fmt::format("{}: no triangles in the file", path));

    if (ai->mNumCameras > 0) {
        const aiCamera& c = *ai->mCameras[0];
        const aiMatrix4x4 world = nodeTransform(nodes, c.mName);
        aiMatrix3x3 rotation(world);
        const nlohmann::json yfov = member(gltf, "/cameras/0/perspective/yfov");
        if (yfov.is_number()) {
            // glTF: the camera sits at its node's origin looking down the node's -z, +y up (Assimp 5.2 also
            // copies the node's translation into the camera's position, which would count it twice).
            scene.camera.position = toVec3(world * aiVector3D(0, 0, 0));
            scene.camera.target = scene.camera.position + normalize(toVec3(rotation * aiVector3D(0, 0, -1)));
            scene.camera.up = normalize(toVec3(rotation * aiVector3D(0, 1, 0)));
            scene.camera.fovY = yfov.get<double>() * 180.0 / kPi;
        } else {
            const Vec3 position = toVec3(world * c.mPosition);
            scene.camera.position = position;
            scene.camera.target = position + normalize(toVec3(rotation * c.mLookAt));
            scene.camera.up = normalize(toVec3(rotation * c.mUp));
            // Assimp gives half the horizontal field of view; the vertical one follows from the aspect ratio.
            const double aspect = c.mAspect > 0 ? c.mAspect : 1.0;
            scene.camera.fovY = 2.0 * std::atan(std::tan(static_cast<double>(c.mHorizontalFOV)) / aspect) * 180.0 / kPi;
        }
    } else {
        scene.camera = scene.automaticCamera();
    }

    for (unsigned i = 0; i < ai->mNumLights; ++i) {
        const aiLight& l = *ai->mLights[i];
        const aiMatrix4x4 world = nodeTransform(nodes, l.mName);
        aiMatrix3x3 rotation(world);
        Light light;
        light.intensity = toColor(l.mColorDiffuse);
        light.position = toVec3(world * l.mPosition);
        light.direction = toVec3(rotation * l.mDirection);
        if (length(light.direction) == 0) light.direction = Vec3(0, -1, 0);
        light.direction = normalize(light.direction);
        switch (l.mType) {
            case aiLightSource_POINT: light.type = Light::Type::Point; break;
            case aiLightSource_DIRECTIONAL: light.type = Light::Type::Directional; break;
            case aiLightSource_SPOT:
                // Half-angles from the axis, as glTF gives them.
                light.type = Light::Type::Spot;
                light.cosOuter = std::cos(std::clamp(static_cast<double>(l.mAngleOuterCone), 1e-3, kPi / 2));
                light.cosInner = std::min(std::cos(std::clamp(static_cast<double>(l.mAngleInnerCone), 0.0, kPi / 2)), 1.0);
                if (!(light.cosInner > light.cosOuter)) light.cosInner = std::min(1.0, light.cosOuter + 1e-3);
                break;
            default:
                scene.warnings.push_back(fmt::format("{}: light '{}' is of a kind symphong does not have (area/ambient); ignored", path, l.mName.C_Str()));
                continue;
        }
        if (isFinite(light.intensity) && minComponent(light.intensity) >= 0) scene.lights.push_back(light);
    }
    return scene;
}

}  // namespace symphong
