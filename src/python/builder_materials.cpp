// python/builder_materials.cpp — the materials of Scene.from_arrays (python/builder.cpp): Phong numbers, or
// Blender's Principled ones mapped by the loaders' own function (scene/exporter_conventions.h; with texture
// maps, the glTF reader's metallic-roughness model of materials/phong.h, point by point), an emission and
// texture maps given as files or image arrays, through the loaders' texture table (scene/surface.h).
#include "io/input_error.h"
#include "python/builder.h"
#include "scene/exporter_conventions.h"
#include "texture/texture_io.h"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <set>

namespace symphong::pybuild {

namespace {

WrapMode wrapFrom(const std::string& name, const std::string& where) {
    if (name == "repeat") return WrapMode::Repeat;
    if (name == "clamp") return WrapMode::Clamp;
    if (name == "mirror") return WrapMode::Mirror;
    throw InputError(fmt::format("{}: wrap '{}' is not repeat, clamp or mirror", where, name));
}

/// One texture map of a material: a file path, an image array, or a dict {"image": path or array,
/// "wrap": "repeat" | "clamp" | "mirror" or a pair, "srgb": bool (uint8 arrays and 8-bit files: whether
/// colour channels are sRGB-encoded; default: by the map), "transform": 6 numbers (TextureRef)}.
TextureRef textureRef(const py::handle& spec, TextureEncoding encoding, const std::string& where, TextureTable& table) {
    TextureRef ref;
    py::object image = py::reinterpret_borrow<py::object>(spec);
    WrapMode wu = WrapMode::Repeat, wv = WrapMode::Repeat;
    if (py::isinstance<py::dict>(spec)) {
        const py::dict d = spec.cast<py::dict>();
        for (const auto& [k, v] : d) {
            const std::string key = py::str(k).cast<std::string>();
            if (key == "image") {
                image = py::reinterpret_borrow<py::object>(v);
            } else if (key == "wrap") {
                if (py::isinstance<py::str>(v)) {
                    wu = wv = wrapFrom(v.cast<std::string>(), where + ".wrap");
                } else {
                    const auto pair = v.cast<std::vector<std::string>>();
                    if (pair.size() != 2) throw InputError(fmt::format("{}.wrap: expected a mode or a pair (u, v)", where));
                    wu = wrapFrom(pair[0], where + ".wrap"), wv = wrapFrom(pair[1], where + ".wrap");
                }
            } else if (key == "srgb") {
                encoding = v.cast<bool>() ? TextureEncoding::Srgb : TextureEncoding::Linear;
            } else if (key == "transform") {
                const py::array_t<double, py::array::c_style> t = floatRows(v, where + ".transform", 0);
                if (t.size() != 6)
                    throw InputError(fmt::format("{}.transform: expected 6 numbers (a, b, c, d, e, f), got {}", where, t.size()));
                std::copy(t.data(), t.data() + 6, ref.transform.begin());
            } else {
                throw InputError(fmt::format("{}: unknown key '{}' (allowed: image, wrap, srgb, transform)", where, key));
            }
        }
        if (!d.contains("image")) throw InputError(fmt::format("{}: a texture dict needs \"image\" (a path or an array)", where));
    }
    if (py::isinstance<py::str>(image) || py::hasattr(image, "__fspath__")) {
        const std::string path = py::str(py::module_::import("os").attr("fspath")(image)).cast<std::string>();
        ref.index = table.file(path, encoding, where);
    } else {
        const py::array arr = py::array::ensure(image);
        if (!arr) throw py::type_error(fmt::format("{}: expected a file path, an image array or a dict", where));
        const Texture tex = textureFromArray(arr, encoding, where);
        ref.index = table.add(where, encoding, [&] { return tex; });
    }
    ref.index = table.withWrap(ref.index, wu, wv);
    return ref;
}

const std::set<std::string> kMaterialKeys = {"name",
                                             "rho_d",
                                             "rho_s",
                                             "n",
                                             "emission",
                                             "base_color",
                                             "metallic",
                                             "specular",
                                             "roughness",
                                             "diffuse_texture",
                                             "specular_texture",
                                             "exponent_texture",
                                             "base_color_texture",
                                             "metallic_roughness_texture",
                                             "emission_texture",
                                             "alpha_texture",
                                             "normal_texture",
                                             "normal_scale",
                                             "bump_texture",
                                             "bump_scale"};

}  // namespace

Texture textureFromArray(const py::array& raw, TextureEncoding encoding, const std::string& where) {
    if (raw.ndim() != 2 && raw.ndim() != 3)
        throw InputError(fmt::format("{}: expected an image array of shape (H, W) or (H, W, C), got shape {}", where, shapeText(raw)));
    const py::ssize_t h = raw.shape(0), w = raw.shape(1), c = raw.ndim() == 3 ? raw.shape(2) : 1;
    if (h < 1 || w < 1 || c < 1 || c > 4 || h > 65536 || w > 65536)
        throw InputError(fmt::format("{}: an image array of shape {} (at most 65536 x 65536, 1 to 4 channels)", where, shapeText(raw)));
    const char kind = raw.dtype().kind();
    if (kind == 'u' && raw.itemsize() == 1) {
        const auto a = py::array_t<std::uint8_t, py::array::c_style | py::array::forcecast>::ensure(raw);
        return textureFrom8Bit(where, static_cast<int>(w), static_cast<int>(h), static_cast<int>(c), a.data(), encoding);
    }
    if (kind != 'f')
        throw py::type_error(
            fmt::format("{}: expected a uint8 or float image array, got dtype {}", where, py::str(raw.dtype()).cast<std::string>()));
    const auto a = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(raw);
    std::vector<float> texels(a.data(), a.data() + a.size());
    for (std::size_t i = 0; i < texels.size(); ++i)
        if (!std::isfinite(texels[i]) || texels[i] < 0)
            throw InputError(fmt::format("{}[{}, {}, {}] = {} is not a finite value >= 0", where, i / c / w, i / c % w, i % c, texels[i]));
    return Texture(where, static_cast<int>(w), static_cast<int>(h), static_cast<int>(c), std::move(texels));
}

/// Material `index` from its dict: Phong numbers (rho_d, rho_s, n) or Blender's Principled ones
/// (base_color, metallic, specular, roughness: the loaders' mapping, scene/exporter_conventions.h), an
/// emission and texture maps.
PhongMaterial material(const py::handle& spec, std::size_t index, TextureTable& table) {
    const std::string where = fmt::format("materials[{}]", index);
    if (!py::isinstance<py::dict>(spec)) throw py::type_error(fmt::format("{}: expected a dict", where));
    const py::dict d = spec.cast<py::dict>();
    for (const auto& item : d) {
        const std::string key = py::str(item.first).cast<std::string>();
        if (!kMaterialKeys.count(key))
            throw InputError(fmt::format("{}: unknown key '{}' (allowed: {})", where, key, fmt::join(kMaterialKeys, ", ")));
    }
    const auto has = [&](const char* k) { return d.contains(k); };
    const auto at = [&](const char* k) { return d[py::str(k)]; };
    const bool principled = has("base_color") || has("metallic") || has("specular") || has("roughness") || has("base_color_texture") ||
                            has("metallic_roughness_texture");
    const bool phong =
        has("rho_d") || has("rho_s") || has("n") || has("diffuse_texture") || has("specular_texture") || has("exponent_texture");
    if (principled && phong)
        throw InputError(
            fmt::format("{}: give either Phong keys (rho_d, rho_s, n, diffuse/specular/exponent_texture) or Principled ones "
                        "(base_color, metallic, specular, roughness, base_color/metallic_roughness_texture), not both",
                        where));
    PhongMaterial m;
    m.name = has("name") ? at("name").cast<std::string>() : fmt::format("material{}", index);
    MaterialTextures& tx = m.textures;
    const std::string w = where + ".";
    if (principled) {
        const Color base = has("base_color") ? colour(at("base_color"), w + "base_color") : Color(0.8);
        const double metallic = has("metallic") ? nonNegative(at("metallic"), w + "metallic") : 0.0;
        const double specular = has("specular") ? nonNegative(at("specular"), w + "specular") : 0.5;
        const double roughness = has("roughness") ? nonNegative(at("roughness"), w + "roughness") : 0.5;
        blenderPrincipledToPhong(base, metallic, specular, roughness, m.rhoD, m.rhoS, m.exponent);
        if (has("base_color_texture") || has("metallic_roughness_texture")) {
            tx.model = MaterialTextures::Model::MetallicRoughness;
            tx.baseColor = base;
            tx.metallic = std::clamp(metallic, 0.0, 1.0);
            tx.roughness = std::clamp(roughness, 0.0, 1.0);
            tx.specularF0 = Color(std::clamp(0.08 * specular, 0.0, 1.0));
            if (has("base_color_texture"))
                tx.diffuse = textureRef(at("base_color_texture"), TextureEncoding::Srgb, w + "base_color_texture", table);
            if (has("metallic_roughness_texture"))
                tx.metallicRoughness =
                    textureRef(at("metallic_roughness_texture"), TextureEncoding::Linear, w + "metallic_roughness_texture", table);
        }
    } else {
        m.rhoD = has("rho_d") ? colour(at("rho_d"), w + "rho_d") : Color(0.7);
        m.rhoS = has("rho_s") ? colour(at("rho_s"), w + "rho_s") : Color(0.0);
        m.exponent = has("n") ? nonNegative(at("n"), w + "n") : 1.0;
        if (has("diffuse_texture")) tx.diffuse = textureRef(at("diffuse_texture"), TextureEncoding::Srgb, w + "diffuse_texture", table);
        if (has("specular_texture")) tx.specular = textureRef(at("specular_texture"), TextureEncoding::Srgb, w + "specular_texture", table);
        if (has("exponent_texture"))
            tx.exponent = textureRef(at("exponent_texture"), TextureEncoding::Linear, w + "exponent_texture", table);
    }
    if (has("emission")) m.emission = colour(at("emission"), w + "emission");
    if (has("emission_texture")) tx.emission = textureRef(at("emission_texture"), TextureEncoding::Srgb, w + "emission_texture", table);
    if (has("alpha_texture")) tx.alpha = textureRef(at("alpha_texture"), TextureEncoding::Linear, w + "alpha_texture", table);
    if (has("normal_texture")) tx.normal = textureRef(at("normal_texture"), TextureEncoding::Linear, w + "normal_texture", table);
    if (has("normal_scale")) tx.normalScale = finiteNumber(at("normal_scale"), w + "normal_scale");
    if (has("bump_texture")) tx.bump = textureRef(at("bump_texture"), TextureEncoding::Linear, w + "bump_texture", table);
    if (has("bump_scale")) tx.bumpScale = finiteNumber(at("bump_scale"), w + "bump_scale");
    return m;
}

}  // namespace symphong::pybuild
