#include "scene/surface.h"

#include "io/input_error.h"
#include "texture/texture_io.h"

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <functional>

namespace symphong {

namespace {

/// Looks a TextureRef up at uv through its affine map.
const Texture& lookup(const Scene& scene, const TextureRef& ref, const TexCoord& uv, double& u, double& v) {
    u = ref.u(uv.u, uv.v);
    v = ref.v(uv.u, uv.v);
    return scene.textures[static_cast<std::size_t>(ref.index)];
}

Color rgbAt(const Scene& scene, const TextureRef& ref, const TexCoord& uv) {
    double u, v;
    const Texture& t = lookup(scene, ref, uv, u, v);
    return t.rgb(u, v);
}

double channelAt(const Scene& scene, const TextureRef& ref, const TexCoord& uv, int c) {
    double u, v;
    const Texture& t = lookup(scene, ref, uv, u, v);
    return t.channel(u, v, c);
}

}  // namespace

bool Scene::hasCutOuts() const {
    return std::any_of(materials.begin(), materials.end(), [](const PhongMaterial& m) { return m.textures.alpha.present(); });
}

TexCoord texcoordAt(const Scene& scene, const Triangle& tri, double b1, double b2) {
    if (tri.t[0] < 0) return {b1, b2};
    const double b0 = 1.0 - b1 - b2;
    const auto& a = scene.uvs[static_cast<std::size_t>(tri.t[0])];
    const auto& b = scene.uvs[static_cast<std::size_t>(tri.t[1])];
    const auto& c = scene.uvs[static_cast<std::size_t>(tri.t[2])];
    return {a[0] * b0 + b[0] * b1 + c[0] * b2, a[1] * b0 + b[1] * b1 + c[1] * b2};
}

const PhongMaterial& materialAt(const Scene& scene, const PhongMaterial& m, const TexCoord& uv, PhongMaterial& out) {
    const MaterialTextures& tx = m.textures;
    if (!tx.reflectance()) return m;
    if (tx.model == MaterialTextures::Model::MetallicRoughness) {
        // glTF: the approximation of the constant mapping (materials/phong.h), per point.
        const Color base = tx.diffuse.present() ? tx.baseColor * rgbAt(scene, tx.diffuse, uv) : tx.baseColor;
        double metallic = tx.metallic, roughness = tx.roughness;
        if (tx.metallicRoughness.present()) {
            roughness *= channelAt(scene, tx.metallicRoughness, uv, 1);  // G
            metallic *= channelAt(scene, tx.metallicRoughness, uv, 2);   // B
        }
        metallicRoughnessToPhong(base, std::clamp(metallic, 0.0, 1.0), roughness, tx.specularF0, out.rhoD, out.rhoS, out.exponent);
    } else {
        out.rhoD = tx.diffuse.present() ? m.rhoD * rgbAt(scene, tx.diffuse, uv) : m.rhoD;
        out.rhoS = tx.specular.present() ? m.rhoS * rgbAt(scene, tx.specular, uv) : m.rhoS;
        out.exponent = tx.exponent.present() ? m.exponent * channelAt(scene, tx.exponent, uv, 0) : m.exponent;
    }
    clampEnergy(out.rhoD, out.rhoS);
    out.emission = m.emission;
    return out;
}

Color emissionAt(const Scene& scene, const PhongMaterial& m, const TexCoord& uv) {
    if (!m.textures.emission.present()) return m.emission;
    return m.emission * rgbAt(scene, m.textures.emission, uv);
}

bool cutOutAt(const Scene& scene, const PhongMaterial& m, const TexCoord& uv) {
    if (!m.textures.alpha.present()) return false;
    double u, v;
    const Texture& t = lookup(scene, m.textures.alpha, uv, u, v);
    return t.coverage(u, v) < 0.5;
}

std::int32_t TextureTable::add(const std::string& key, TextureEncoding encoding, const std::function<Texture()>& decode) {
    const auto k = std::make_pair(key, static_cast<int>(encoding));
    if (const auto it = loaded_.find(k); it != loaded_.end()) return it->second;
    scene_.textures.push_back(decode());
    const auto index = static_cast<std::int32_t>(scene_.textures.size() - 1);
    loaded_[k] = index;
    return index;
}

std::int32_t TextureTable::withWrap(std::int32_t index, WrapMode u, WrapMode v) {
    if (index < 0) return index;
    const auto key = std::make_tuple(index, static_cast<int>(u), static_cast<int>(v));
    if (const auto it = wrapped_.find(key); it != wrapped_.end()) return it->second;
    std::int32_t out = index;
    if (!wrapSet_.insert(index).second) {  // another material already wraps this image its own way
        Texture copy = scene_.textures[static_cast<std::size_t>(index)];
        scene_.textures.push_back(std::move(copy));
        out = static_cast<std::int32_t>(scene_.textures.size() - 1);
    }
    Texture& t = scene_.textures[static_cast<std::size_t>(out)];
    t.wrapU = u;
    t.wrapV = v;
    wrapped_[key] = out;
    return out;
}

std::int32_t TextureTable::file(const std::string& path, TextureEncoding encoding, const std::string& where) {
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) {
        scene_.warnings.push_back(fmt::format("{}: texture '{}' not found; using the material's constant instead", where, path));
        return -1;
    }
    return add(path, encoding, [&] { return loadTextureFile(path, encoding); });
}

}  // namespace symphong
