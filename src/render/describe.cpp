#include "render/describe.h"

#include "lights/emitters.h"
#include "lights/kinds.h"

#include <fmt/format.h>

namespace symphong {

namespace {

std::string materialMaps(const MaterialTextures& tx) {
    std::string maps;
    const auto add = [&](const char* what, const TextureRef& r) {
        if (r.present()) maps += fmt::format("{}{} = texture {}", maps.empty() ? "" : ", ", what, r.index);
    };
    const bool pbr = tx.model == MaterialTextures::Model::MetallicRoughness;
    add(pbr ? "base colour" : "rho_d", tx.diffuse);
    add("rho_s", tx.specular);
    add("n", tx.exponent);
    add("metallic-roughness", tx.metallicRoughness);
    add("emission", tx.emission);
    add("cut-out", tx.alpha);
    add("normal", tx.normal);
    if (tx.normal.present() && tx.normalScale != 1) maps += fmt::format(" (scale {:.4g})", tx.normalScale);
    add("bump", tx.bump);
    if (tx.bump.present()) maps += fmt::format(" (height x {:.4g} scene units)", tx.bumpScale);
    if (pbr)
        maps += fmt::format(" (glTF factors: base colour {}, metallic {:.4g}, roughness {:.4g})", formatTriple(tx.baseColor), tx.metallic,
                            tx.roughness);
    else if (tx.reflectance())
        maps += " (times the constants above)";
    return maps;
}

std::string describeMaterials(const Scene& s) {
    std::vector<std::size_t> uses(s.materials.size(), 0);
    for (const Triangle& t : s.triangles) ++uses[t.material];
    std::string out = fmt::format("materials   {}\n", s.materials.size());
    for (std::size_t i = 0; i < s.materials.size(); ++i) {
        const PhongMaterial& m = s.materials[i];
        out += fmt::format("  {:<20} rho_d {}  rho_s {}  n {:.6g}  emission {}  ({} triangles)\n", "'" + m.name + "'", formatTriple(m.rhoD),
                           formatTriple(m.rhoS), m.exponent, formatTriple(m.emission), uses[i]);
        if (m.textures.any()) out += fmt::format("  {:<20} maps: {}\n", "", materialMaps(m.textures));
    }
    return out;
}

std::string describeTextures(const Scene& s) {
    std::uint64_t textureBytes = 0;
    for (const Texture& t : s.textures) textureBytes += t.bytes();
    std::string out = fmt::format("textures    {} ({:.3g} MiB), {} texture coordinates, {} tangents\n", s.textures.size(),
                                  static_cast<double>(textureBytes) / (1024.0 * 1024.0), s.uvs.size(), s.tangents.size());
    for (std::size_t i = 0; i < s.textures.size(); ++i) {
        const Texture& t = s.textures[i];
        out += fmt::format("  {:<3} {} x {}, {} channel{}, wrap {}/{}: {}\n", i, t.width(), t.height(), t.channels(),
                           t.channels() > 1 ? "s" : "", wrapModeName(t.wrapU), wrapModeName(t.wrapV), t.name());
    }
    return out;
}

}  // namespace

std::string describeScene(const Scene& s, const std::string& spec) {
    Vec3 lo, hi;
    s.bounds(lo, hi);
    std::size_t emissive = 0;
    for (const Triangle& t : s.triangles) emissive += s.materials[t.material].isEmissive();
    std::string out = fmt::format("scene       {} (from {})\n", s.name, spec);
    out += fmt::format("triangles   {} ({} emissive), {} vertices, {} shading normals\n", s.triangles.size(), emissive, s.positions.size(),
                       s.normals.size());
    out += fmt::format("bounds      {} to {} (size {})\n", formatTriple(lo), formatTriple(hi), formatTriple(hi - lo));
    out += fmt::format("camera      position {}, target {}, up {}, vertical fov {:.4g} degrees\n", formatTriple(s.camera.position),
                       formatTriple(s.camera.target), formatTriple(s.camera.up), s.camera.fovY);
    out += describeMaterials(s);
    out += fmt::format("lights      {}\n", s.lights.size());
    for (const Light& l : s.lights) {
        const auto e = makeLightEmitter(l);
        out += fmt::format("  {:<11} {}\n", e->kind(), e->describe());
    }
    out += fmt::format("environment {}\n", makeBackgroundEmitter(s)->describe());
    out += describeTextures(s);
    if (!s.renderSettings.empty()) out += fmt::format("render      {} (the scene's own settings, under the command line's)\n", s.renderSettings);
    out += fmt::format("warnings    {}\n", s.warnings.size());
    for (const std::string& w : s.warnings) out += fmt::format("  {}\n", w);
    return out;
}

}  // namespace symphong
