#include "scene/assimp_materials.h"

#include "scene/exporter_conventions.h"

#include "io/files.h"
#include "io/input_error.h"
#include "io/memory.h"
#include "scene/shading_normal.h"
#include "texture/texture_io.h"

#include <assimp/GltfMaterial.h>
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <functional>

namespace symphong {

namespace {

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

/// A glTF textureInfo's KHR_texture_transform in symphong's coordinates. The extension maps
/// (s, t) -> M (s, t, 1) with M = T R S, T the offset, R = [cos r, -sin r; sin r, cos r], S the scale,
/// in glTF's coordinates where t runs down the image; symphong's v = 1 - t (Assimp flips it), so
/// u' = m00 u - m01 v + (m01 + m02) and v' = -m10 u + m11 v + (1 - m11 - m12). A second set of texture
/// coordinates (texCoord > 0) is not read: a warning.
std::array<double, 6> gltfTextureTransform(const nlohmann::json& info, const std::string& where, Scene& scene) {
    if (number(info, "/texCoord", 0) != 0 || number(info, "/extensions/KHR_texture_transform/texCoord", 0) != 0)
        scene.warnings.push_back(
            fmt::format("{}: uses a second set of texture coordinates (texCoord); symphong reads only the first", where));
    const nlohmann::json x = member(info, "/extensions/KHR_texture_transform");
    if (!x.is_object()) return {1, 0, 0, 0, 1, 0};
    const double ox = number(x, "/offset/0", 0), oy = number(x, "/offset/1", 0), r = number(x, "/rotation", 0);
    const double sx = number(x, "/scale/0", 1), sy = number(x, "/scale/1", 1);
    const double m00 = sx * std::cos(r), m01 = -sy * std::sin(r), m10 = sx * std::sin(r), m11 = sy * std::cos(r);
    const std::array<double, 6> m{m00, -m01, m01 + ox, -m10, m11, 1 - m11 - oy};
    if (!std::all_of(m.begin(), m.end(), [](double v) { return std::isfinite(v); }))
        throw InputError(fmt::format("{}: its KHR_texture_transform gives a transform that is not finite", where));
    return m;
}

/// Where a glTF material keeps the textureInfo of each texture type that symphong reads.
const char* gltfTextureInfo(aiTextureType type) {
    switch (type) {
        case aiTextureType_BASE_COLOR:
        case aiTextureType_DIFFUSE:
            return "/pbrMetallicRoughness/baseColorTexture";
        case aiTextureType_UNKNOWN:
            return "/pbrMetallicRoughness/metallicRoughnessTexture";
        case aiTextureType_NORMALS:
            return "/normalTexture";
        case aiTextureType_EMISSIVE:
            return "/emissiveTexture";
        default:
            return nullptr;
    }
}

/// Normal and bump maps: a normal map (glTF's normalTexture with its scale; FBX's and Collada's normal
/// maps, with FBX's BumpFactor), and a height map, which may hold a normal map too (scene/shading_normal.h
/// decides).
void attachNormalMaps(const aiMaterial& m, const std::function<TextureRef(aiTextureType, TextureEncoding)>& tex, const nlohmann::json& gltf,
                      Scene& scene, const std::string& where, MaterialTextures& tx) {
    tx.normal = tex(aiTextureType_NORMALS, TextureEncoding::Linear);
    float bumpScaling = 1;  // FBX's BumpFactor (Blender's normal map strength)
    tx.normalScale = gltf.is_object()                                          ? number(gltf, "/normalTexture/scale", 1.0)
                     : m.Get(AI_MATKEY_BUMPSCALING, bumpScaling) == AI_SUCCESS ? static_cast<double>(bumpScaling)
                                                                               : 1.0;
    const TextureRef height = tex(aiTextureType_HEIGHT, TextureEncoding::Linear);
    if (!height.present()) return;
    if (!looksLikeNormalMap(scene.textures[static_cast<std::size_t>(height.index)])) {
        tx.bump = height;
        return;
    }
    if (tx.normal.present())
        scene.warnings.push_back(fmt::format("{}: a second normal map (its bump map); ignored", where));
    else
        tx.normal = height;
}

/// Attaches material index i's textures: Phong maps (diffuse, specular, shininess) or glTF's
/// metallic-roughness ones (base colour, metallic-roughness), emissive, normal and bump maps, and a
/// cut-out (an opacity map, or glTF's alphaMode MASK/BLEND on the base colour's alpha). `gltf` is the
/// material's glTF JSON (null for other formats): its texture transforms and normal scale.
void attachTextures(const aiScene& ai, const aiMaterial& m, PhongMaterial& out, bool pbr, const aiColor4D& base, float metallic,
                    float roughness, const nlohmann::json& gltf, TextureTable& table, Scene& scene, const std::string& path) {
    MaterialTextures& tx = out.textures;
    const std::string where = fmt::format("{}: material '{}'", path, out.name);
    const std::function<TextureRef(aiTextureType, TextureEncoding)> tex = [&](aiTextureType type, TextureEncoding enc) {
        TextureRef ref = assimpTexture(ai, m, type, enc, table, path, out.name);
        const char* info = gltfTextureInfo(type);
        if (ref.present() && gltf.is_object() && info) ref.transform = gltfTextureTransform(member(gltf, info), where, scene);
        return ref;
    };
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
    attachNormalMaps(m, tex, gltf, scene, where, tx);
    for (const auto& [type, what] :
         {std::pair{aiTextureType_DISPLACEMENT, "displacement"}, std::pair{aiTextureType_LIGHTMAP, "occlusion/light"}})
        if (m.GetTextureCount(type) > 0)
            scene.warnings.push_back(
                fmt::format("{}: material '{}': its {} map is not supported by symphong; ignored", path, out.name, what));
    tx.emission = tex(aiTextureType_EMISSIVE, TextureEncoding::Srgb);
    if (!tx.alpha.present()) tx.alpha = tex(aiTextureType_OPACITY, TextureEncoding::Linear);
}

/// A glTF material's dielectric reflectance at normal incidence: ((ior - 1) / (ior + 1))^2 (0.04 at the
/// default ior 1.5; KHR_materials_ior), times KHR_materials_specular's specularColorFactor, at most 1,
/// times its specularFactor. Blender writes specularColorFactor 0 for "Specular 0".
Color gltfSpecularF0(const nlohmann::json& material) {
    const auto nonNegative = [&](const char* pointer, double fallback) {
        const double v = number(material, pointer, fallback);
        return v >= 0 ? v : fallback;
    };
    const double ior = nonNegative("/extensions/KHR_materials_ior/ior", 1.5);
    const double r = (ior - 1) / (ior + 1);
    Color colour(1.0);
    const nlohmann::json c = member(material, "/extensions/KHR_materials_specular/specularColorFactor");
    if (c.is_array() && c.size() == 3)
        for (int k = 0; k < 3; ++k)
            if (c[static_cast<std::size_t>(k)].is_number() && c[static_cast<std::size_t>(k)].get<double>() >= 0)
                colour[k] = c[static_cast<std::size_t>(k)].get<double>();
    const double factor = std::min(nonNegative("/extensions/KHR_materials_specular/specularFactor", 1.0), 1.0);
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
        if (model == aiShadingMode_Gouraud) out.rhoS = Color(0.0);               // <lambert>
        if (model == aiShadingMode_NoShading) out.rhoD = out.rhoS = Color(0.0);  // <constant>: emission only
    }
    if (isBlack(out.rhoS)) out.exponent = std::max(out.exponent, 1.0);
}

}  // namespace

/// The value at a JSON pointer, or null when any step of it is missing or of another type.
nlohmann::json member(const nlohmann::json& j, const std::string& pointer) {
    try {
        const nlohmann::json::json_pointer p(pointer);
        return j.is_object() && j.contains(p) ? j.at(p) : nlohmann::json();
    } catch (const nlohmann::json::exception&) {
        return nullptr;
    }
}

/// A finite number at a JSON pointer, or `fallback`.
double number(const nlohmann::json& j, const std::string& pointer, double fallback) {
    const nlohmann::json v = member(j, pointer);
    return v.is_number() && std::isfinite(v.get<double>()) ? v.get<double>() : fallback;
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
    const double gltfStrength = number(gltf, "/extensions/KHR_materials_emissive_strength/emissiveStrength", 1.0);
    if (gltfStrength >= 0) out.emission *= gltfStrength;
    attachTextures(ai, m, out, pbr, base, metallic, roughness, gltf, table, scene, path);
    return out;
}

}  // namespace symphong
