// scene/assimp_loader.cpp — mesh formats other than OBJ through Assimp (Debian's libassimp-dev): glTF 2.0,
// FBX, Collada, 3DS and the rest Assimp reads (PLY has its own reader, ply_loader.cpp), each first in a
// child process (assimp_guard.h). Meshes are triangulated and placed by their nodes'
// transforms; materials are mapped to Phong parameters by the table in docs/scene-format.md; the
// file's first camera and its point, spot and directional lights are kept. Coordinates stay as the
// file defines them (glTF: y up, metres). Textures (diffuse / base colour, specular, shininess,
// metallic-roughness, emissive, opacity and glTF's alpha mask), from files beside the model or embedded
// in it, go through scene/surface.h's texture table.
#include "scene/scene.h"

#include "scene/assimp_guard.h"
#include "scene/exporter_conventions.h"

#include "io/files.h"
#include "io/input_error.h"
#include "io/memory.h"
#include "scene/surface.h"
#include "texture/texture_io.h"

#include <nlohmann/json.hpp>

#include <assimp/GltfMaterial.h>
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

Vec3 toVec3(const aiVector3D& v) { return {v.x, v.y, v.z}; }
Color toColor(const aiColor3D& c) { return {c.r, c.g, c.b}; }

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

WrapMode wrapMode(int mode) {
    switch (mode) {
        case aiTextureMapMode_Clamp:
        case aiTextureMapMode_Decal:
            return WrapMode::Clamp;
        case aiTextureMapMode_Mirror:
            return WrapMode::Mirror;
        default:
            return WrapMode::Repeat;
    }
}

/// The first texture of `type` on material m, from a file beside the model or embedded in it ("*N"),
/// with its wrap modes; an absent one is a TextureRef without index (a missing file also warns).
TextureRef assimpTexture(const aiScene& ai, const aiMaterial& m, aiTextureType type, TextureEncoding encoding, TextureTable& table,
                         const std::string& path, const std::string& materialName) {
    TextureRef ref;
    if (m.GetTextureCount(type) == 0) return ref;
    aiString file;
    aiTextureMapMode modes[2] = {aiTextureMapMode_Wrap, aiTextureMapMode_Wrap};
    if (m.GetTexture(type, 0, &file, nullptr, nullptr, nullptr, nullptr, modes) != AI_SUCCESS || file.length == 0) return ref;
    const std::string where = fmt::format("{}: material '{}'", path, materialName);
    if (const aiTexture* embedded = ai.GetEmbeddedTexture(file.C_Str())) {
        const std::string name = fmt::format("{}: embedded texture '{}'", path, file.C_Str());
        ref.index = table.add(name, encoding, [&] {
            if (embedded->mHeight == 0)  // compressed (PNG, JPEG, ...): mWidth bytes
                return decodeTexture(name, reinterpret_cast<const unsigned char*>(embedded->pcData), embedded->mWidth, encoding);
            // Raw BGRA8888 texels, mWidth x mHeight, row 0 at the top.
            const std::uint64_t w = embedded->mWidth, h = embedded->mHeight;
            requireMemory(saturatingMultiply(w, h) * 16, fmt::format("{}: a {} x {} texture", name, w, h));
            std::vector<unsigned char> rgba(static_cast<std::size_t>(w * h * 4));
            for (std::size_t i = 0; i < w * h; ++i) {
                const aiTexel& t = embedded->pcData[i];
                rgba[4 * i] = t.r, rgba[4 * i + 1] = t.g, rgba[4 * i + 2] = t.b, rgba[4 * i + 3] = t.a;
            }
            return textureFrom8Bit(name, static_cast<int>(w), static_cast<int>(h), 4, rgba.data(), encoding);
        });
    } else {
        if (file.C_Str()[0] == '*')
            throw InputError(fmt::format("{}: texture '{}' refers to an embedded image the file does not have", where, file.C_Str()));
        std::filesystem::path f = file.C_Str();
        if (f.is_relative()) f = std::filesystem::path(path).parent_path() / f;
        ref.index = table.file(f.string(), encoding, where);
    }
    ref.index = table.withWrap(ref.index, wrapMode(modes[0]), wrapMode(modes[1]));
    return ref;
}

/// Attaches material index i's textures: Phong maps (diffuse, specular, shininess) or glTF's
/// metallic-roughness ones (base colour, metallic-roughness), emissive, and a cut-out (an opacity map,
/// or glTF's alphaMode MASK/BLEND on the base colour's alpha).
void attachTextures(const aiScene& ai, const aiMaterial& m, PhongMaterial& out, bool pbr, const aiColor4D& base, float metallic,
                    float roughness, TextureTable& table, Scene& scene, const std::string& path) {
    MaterialTextures& tx = out.textures;
    const auto tex = [&](aiTextureType type, TextureEncoding enc) { return assimpTexture(ai, m, type, enc, table, path, out.name); };
    if (pbr) {
        tx.diffuse = tex(aiTextureType_BASE_COLOR, TextureEncoding::Srgb);
        if (!tx.diffuse.present()) tx.diffuse = tex(aiTextureType_DIFFUSE, TextureEncoding::Srgb);
        tx.metallicRoughness = tex(aiTextureType_UNKNOWN, TextureEncoding::Linear);  // glTF: G roughness, B metallic
        tx.baseColor = Color(base.r, base.g, base.b);
        tx.metallic = metallic;
        tx.roughness = roughness;
        if (tx.diffuse.present() || tx.metallicRoughness.present()) tx.model = MaterialTextures::Model::MetallicRoughness;
        aiString mode;
        if (m.Get(AI_MATKEY_GLTF_ALPHAMODE, mode) == AI_SUCCESS && std::string(mode.C_Str()) != "OPAQUE" && tx.diffuse.present()) {
            tx.alpha = tx.diffuse;
            if (std::string(mode.C_Str()) == "BLEND")
                scene.warnings.push_back(
                    fmt::format("{}: material '{}' blends by alpha; symphong renders it as a cut-out at alpha 1/2", path, out.name));
        }
    } else {
        tx.diffuse = tex(aiTextureType_DIFFUSE, TextureEncoding::Srgb);
        tx.specular = tex(aiTextureType_SPECULAR, TextureEncoding::Srgb);
        tx.exponent = tex(aiTextureType_SHININESS, TextureEncoding::Linear);
        // A texture with no constant beside it: the constant is 1 (1000 for the exponent), as for MTL.
        aiColor3D c;
        if (tx.diffuse.present() && m.Get(AI_MATKEY_COLOR_DIFFUSE, c) != AI_SUCCESS) out.rhoD = Color(1.0);
        if (tx.specular.present() && m.Get(AI_MATKEY_COLOR_SPECULAR, c) != AI_SUCCESS) out.rhoS = Color(1.0);
        float shininess;
        if (tx.exponent.present() && m.Get(AI_MATKEY_SHININESS, shininess) != AI_SUCCESS) out.exponent = 1000;
    }
    for (const auto& [type, what] :
         {std::pair{aiTextureType_NORMALS, "normal"}, std::pair{aiTextureType_HEIGHT, "bump"},
          std::pair{aiTextureType_DISPLACEMENT, "displacement"}, std::pair{aiTextureType_LIGHTMAP, "occlusion/light"}})
        if (m.GetTextureCount(type) > 0)
            scene.warnings.push_back(
                fmt::format("{}: material '{}': its {} map is not supported by symphong; ignored", path, out.name, what));
    tx.emission = tex(aiTextureType_EMISSIVE, TextureEncoding::Srgb);
    if (!tx.alpha.present()) tx.alpha = tex(aiTextureType_OPACITY, TextureEncoding::Linear);
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

/// A glTF material's dielectric reflectance at normal incidence: ((ior - 1) / (ior + 1))^2 (0.04 at the
/// default ior 1.5; KHR_materials_ior), times KHR_materials_specular's specularColorFactor, at most 1,
/// times its specularFactor. Blender writes specularColorFactor 0 for "Specular 0".
Color gltfSpecularF0(const nlohmann::json& material) {
    const auto number = [&](const char* pointer, double fallback) {
        const nlohmann::json v = member(material, pointer);
        return v.is_number() && std::isfinite(v.get<double>()) && v.get<double>() >= 0 ? v.get<double>() : fallback;
    };
    const double ior = number("/extensions/KHR_materials_ior/ior", 1.5);
    const double r = (ior - 1) / (ior + 1);
    Color colour(1.0);
    const nlohmann::json c = member(material, "/extensions/KHR_materials_specular/specularColorFactor");
    if (c.is_array() && c.size() == 3)
        for (int k = 0; k < 3; ++k)
            if (c[static_cast<std::size_t>(k)].is_number() && c[static_cast<std::size_t>(k)].get<double>() >= 0)
                colour[k] = c[static_cast<std::size_t>(k)].get<double>();
    const double factor = std::min(number("/extensions/KHR_materials_specular/specularFactor", 1.0), 1.0);
    Color f0 = colour * (r * r);
    for (int k = 0; k < 3; ++k) f0[k] = std::min(f0[k], 1.0) * factor;
    return f0;
}

/// A material of the Phong family (FBX, Collada, 3DS): diffuse -> rho_d, specular -> rho_s, shininess ->
/// n, with each format's conventions as Assimp 5.2 hands them over (docs/scene-format.md): FBX's
/// SpecularFactor (Assimp's shininess strength) scales the specular colour; a Collada <lambert> effect has
/// no specular part (Assimp gives it its defaults, 0.4 and 10) and a <constant> one only emits. An FBX
/// that Blender wrote (`blender`) holds its Principled numbers in Blender's own way (exporter_conventions.h).
void mapPhongMaterial(const aiMaterial& m, const std::string& path, bool blender, PhongMaterial& out) {
    aiColor3D c;
    if (m.Get(AI_MATKEY_COLOR_DIFFUSE, c) == AI_SUCCESS) out.rhoD = toColor(c);
    if (m.Get(AI_MATKEY_COLOR_SPECULAR, c) == AI_SUCCESS) out.rhoS = toColor(c);
    float shininess = 0;
    if (m.Get(AI_MATKEY_SHININESS, shininess) == AI_SUCCESS) out.exponent = std::max(0.0f, shininess);
    const std::string ext = lowerExtension(path);
    float strength = 1;
    if (ext == ".fbx" && blender) {  // Blender's Principled numbers (scene/exporter_conventions.h)
        float factor = 0, metallic = 0;
        m.Get(AI_MATKEY_SHININESS_STRENGTH, factor);  // SpecularFactor = Specular / 2
        m.Get(AI_MATKEY_REFLECTIVITY, metallic);      // ReflectionFactor = Metallic
        const double roughness = 1.0 - std::sqrt(std::max(0.0, static_cast<double>(shininess))) / 10.0;
        blenderPrincipledToPhong(out.rhoD, metallic, 2.0 * factor, roughness, out.rhoD, out.rhoS, out.exponent);
        return;
    }
    if (ext == ".fbx" && m.Get(AI_MATKEY_SHININESS_STRENGTH, strength) == AI_SUCCESS && std::isfinite(strength))
        out.rhoS *= std::max(0.0, static_cast<double>(strength));
    int model = 0;
    if (ext == ".dae" && m.Get(AI_MATKEY_SHADING_MODEL, model) == AI_SUCCESS) {
        if (model == aiShadingMode_Gouraud) out.rhoS = Color(0.0);  // <lambert>
        if (model == aiShadingMode_NoShading) out.rhoD = out.rhoS = Color(0.0);  // <constant>: emission only
    }
    if (isBlack(out.rhoS)) out.exponent = std::max(out.exponent, 1.0);
}

/// One material: Phong/Blinn parameters directly (diffuse -> rho_d, specular -> rho_s, shininess -> n,
/// emissive -> Le); a glTF metallic-roughness material by the stated approximation
/// (materials/phong.h metallicRoughnessToPhong) with its specular extensions (`gltf`: the material's own
/// JSON, null for other formats); emission times KHR_materials_emissive_strength.
PhongMaterial mapMaterial(const aiScene& ai, const aiMaterial& m, std::size_t index, const nlohmann::json& gltf, bool blender,
                          TextureTable& table, Scene& scene, const std::string& path) {
    PhongMaterial out;
    aiString name;
    out.name = m.Get(AI_MATKEY_NAME, name) == AI_SUCCESS && name.length > 0 ? name.C_Str() : fmt::format("material{}", index);
    aiColor4D base;
    float metallic = 0, roughness = 1;
    const bool pbr = m.Get(AI_MATKEY_BASE_COLOR, base) == AI_SUCCESS && m.Get(AI_MATKEY_METALLIC_FACTOR, metallic) == AI_SUCCESS;
    if (pbr) {
        m.Get(AI_MATKEY_ROUGHNESS_FACTOR, roughness);
        out.textures.specularF0 = gltf.is_object() ? gltfSpecularF0(gltf) : Color(0.04);
        metallicRoughnessToPhong(Color(base.r, base.g, base.b), metallic, roughness, out.textures.specularF0, out.rhoD, out.rhoS,
                                 out.exponent);
    } else {
        mapPhongMaterial(m, path, blender, out);
    }
    aiColor3D e;
    if (m.Get(AI_MATKEY_COLOR_EMISSIVE, e) == AI_SUCCESS) out.emission = toColor(e);
    float strength = 1;
    if (m.Get(AI_MATKEY_EMISSIVE_INTENSITY, strength) == AI_SUCCESS && strength != 1.0f) out.emission *= static_cast<double>(strength);
    const nlohmann::json gltfStrength = member(gltf, "/extensions/KHR_materials_emissive_strength/emissiveStrength");
    if (gltfStrength.is_number() && std::isfinite(gltfStrength.get<double>()) && gltfStrength.get<double>() >= 0)
        out.emission *= gltfStrength.get<double>();
    attachTextures(ai, m, out, pbr, base, metallic, roughness, table, scene, path);
    return out;
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
        }
        scene.triangles.push_back(t);
    }
}

/// The file's first camera, placed by its node.
Camera fileCamera(const aiScene& ai, const std::vector<std::pair<std::string, aiMatrix4x4>>& nodes, const nlohmann::json& gltf,
                  const std::string& path) {
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
    double half = c.mHorizontalFOV;
    if (fbx && (aiGetVersionMajor() < 5 || (aiGetVersionMajor() == 5 && aiGetVersionMinor() < 3))) half *= 0.5;
    if (lowerExtension(path) == ".dae") half *= 0.5;
    camera.fovY = 2.0 * std::atan(std::tan(half) / aspect) * 180.0 / kPi;
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
    if (!ai)
        throw InputError(fmt::format("{}: cannot read it (Assimp: {})", path, importer.GetErrorString()));

    Scene scene;
    scene.name = std::filesystem::path(path).stem().string();
    TextureTable table(scene);
    const bool blender = lowerExtension(path) == ".fbx" && fbxWrittenByBlender(path);
    for (unsigned i = 0; i < ai->mNumMaterials; ++i)
        scene.materials.push_back(
            mapMaterial(*ai, *ai->mMaterials[i], i, member(gltf, fmt::format("/materials/{}", i)), blender, table, scene, path));
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
    scene.camera = ai->mNumCameras > 0 ? fileCamera(*ai, nodes, gltf, path) : scene.automaticCamera();
    for (unsigned i = 0; i < ai->mNumLights; ++i) addLight(*ai->mLights[i], nodes, path, scene);
    return scene;
}

std::string assimpVersion() { return fmt::format("{}.{}.{}", aiGetVersionMajor(), aiGetVersionMinor(), aiGetVersionPatch()); }

}  // namespace symphong
