// Wavefront OBJ/MTL loading. tinyobjloader does the parsing; before it runs, a line-by-line pass over
// the OBJ (and its MTL) rejects what tinyobjloader would accept silently or report without a line:
// non-finite numbers, faces with fewer than 3 vertices, indices of 0 or out of range; it also counts
// the elements so that a mesh too large for memory is refused before it is parsed. Texture maps of the
// MTL (map_Kd, map_Ks, map_Ns, map_d, map_Ke) go through scene/surface.h's texture table.
#include "io/files.h"
#include "io/input_error.h"
#include "io/memory.h"
#include "scene/scene.h"

#include "scene/exporter_conventions.h"
#include "scene/shading_normal.h"
#include "scene/surface.h"

#include <fmt/format.h>
#include <tiny_obj_loader.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>

namespace symphong {

namespace {

std::vector<std::string> splitWords(const std::string& line) {
    std::vector<std::string> words;
    std::istringstream in(line);
    std::string w;
    while (in >> w) words.push_back(w);
    return words;
}

std::string trim(const std::string& s) {
    const auto b = s.find_first_not_of(" \t\r\n");
    if (b == std::string::npos) return {};
    const auto e = s.find_last_not_of(" \t\r\n");
    return s.substr(b, e - b + 1);
}

/// Parses a whole token as a finite double that single precision can hold (tinyobjloader keeps
/// floats; a larger value would overflow its conversion); false otherwise.
bool parseFinite(const std::string& token, double& value) {
    errno = 0;
    char* end = nullptr;
    value = std::strtod(token.c_str(), &end);
    return end != token.c_str() && *end == '\0' && std::isfinite(value) && std::abs(value) <= 3.0e38;
}

/// Calls fn(lineNumber, words) for each non-empty, non-comment line of a text.
template <class Fn>
void forEachLine(const std::string& text, Fn&& fn) {
    // Lines end at \n, \r\n or a lone \r, as tinyobjloader reads them (a lone \r must not hide a line
    // from this check that tinyobjloader then parses).
    std::string normalized = text;
    for (std::size_t i = 0; i < normalized.size(); ++i)
        if (normalized[i] == '\r') {
            if (i + 1 < normalized.size() && normalized[i + 1] == '\n')
                normalized[i] = ' ';
            else
                normalized[i] = '\n';
        }
    std::istringstream in(normalized);
    std::string line;
    int number = 0;
    while (std::getline(in, line)) {
        ++number;
        const auto hash = line.find('#');
        if (hash != std::string::npos) line.erase(hash);
        auto words = splitWords(line);
        if (!words.empty()) fn(number, words);
    }
}

struct ObjScan {
    std::set<std::string> usedMaterials;
    std::vector<std::string> mtllibs;
    std::uint64_t counts[3] = {0, 0, 0};  ///< v, vt, vn lines
    std::uint64_t corners = 0;            ///< face corners over all f lines
    std::uint64_t triangles = 0;          ///< triangles the f lines make (a face of k corners: k - 2)
};

/// What an MTL file states for one material: the file, and the line of each keyword it gives (so a map
/// without its constant can take 1 as the constant, and a missing texture can be reported at its line).
struct MtlMaterial {
    std::string file;
    std::map<std::string, int> keys;
    bool blender = false;  ///< the MTL is Blender's (scene/exporter_conventions.h)
};
using MtlKeys = std::map<std::string, MtlMaterial>;

ObjScan validateObj(const std::string& path, const std::string& text) {
    ObjScan scan;
    forEachLine(text, [&](int line, const std::vector<std::string>& w) {
        const std::string& key = w[0];
        const auto numbers = [&](std::size_t minimum, const char* what) {
            if (w.size() - 1 < minimum)
                throw InputError(fmt::format("{}:{}: '{}' line needs {} numbers, got {}", path, line, key, minimum, w.size() - 1));
            for (std::size_t i = 1; i < w.size(); ++i) {
                double value;
                if (!parseFinite(w[i], value))
                    throw InputError(fmt::format("{}:{}: {} '{}' is not a finite number within single precision", path, line, what, w[i]));
            }
        };
        if (key == "v") {
            numbers(3, "vertex coordinate");
            ++scan.counts[0];
        } else if (key == "vt") {
            numbers(1, "texture coordinate");
            ++scan.counts[1];
        } else if (key == "vn") {
            numbers(3, "normal component");
            ++scan.counts[2];
        } else if (key == "f") {
            if (w.size() - 1 < 3)
                throw InputError(fmt::format("{}:{}: face has {} vertices, at least 3 are needed", path, line, w.size() - 1));
            static const char* kinds[3] = {"vertex", "texture", "normal"};
            scan.corners += w.size() - 1;
            scan.triangles += w.size() - 3;
            for (std::size_t i = 1; i < w.size(); ++i) {
                std::size_t start = 0;
                for (int k = 0; k < 3 && start <= w[i].size(); ++k) {
                    const auto slash = w[i].find('/', start);
                    const std::string part = w[i].substr(start, slash == std::string::npos ? std::string::npos : slash - start);
                    if (!part.empty()) {
                        char* end = nullptr;
                        const long idx = std::strtol(part.c_str(), &end, 10);
                        if (*end != '\0') throw InputError(fmt::format("{}:{}: face index '{}' is not an integer", path, line, w[i]));
                        if (idx == 0)
                            throw InputError(
                                fmt::format("{}:{}: face {} index 0 in '{}' (OBJ indices start at 1)", path, line, kinds[k], w[i]));
                        const long defined = static_cast<long>(scan.counts[k]);
                        const long resolved = idx > 0 ? idx : defined + idx + 1;
                        if (resolved < 1 || resolved > defined)
                            throw InputError(fmt::format("{}:{}: face {} index {} in '{}' is out of range ({} defined so far)", path, line,
                                                         kinds[k], idx, w[i], defined));
                    } else if (k == 0) {
                        throw InputError(fmt::format("{}:{}: face corner '{}' has no vertex index", path, line, w[i]));
                    }
                    if (slash == std::string::npos) break;
                    start = slash + 1;
                }
            }
        } else if (key == "vw") {
            // Skin weights (unused here): "vw vertex joint weight ...". tinyobjloader parses the ids as int
            // and the weights as float; refuse what would overflow either.
            for (std::size_t i = 1; i < w.size(); ++i) {
                double value;
                if (!parseFinite(w[i], value) || ((i % 2 == 1) && (value < 0 || value > 2147483647.0 || value != std::floor(value))))
                    throw InputError(fmt::format("{}:{}: skin weight line value '{}' is not {}", path, line, w[i],
                                                 i % 2 == 1 ? "an index" : "a finite number"));
            }
        } else if (key == "usemtl" && w.size() >= 2) {
            scan.usedMaterials.insert(trim(w[1]));
        } else if (key == "mtllib" && w.size() >= 2) {
            for (std::size_t i = 1; i < w.size(); ++i) scan.mtllibs.push_back(w[i]);
        }
    });
    return scan;
}

MtlKeys validateMtl(const std::string& path, const std::string& text) {
    MtlKeys keys;
    std::string current;
    forEachLine(text, [&](int line, const std::vector<std::string>& w) {
        const std::string& key = w[0];
        if (key == "newmtl" && w.size() >= 2)
            current = trim(w[1]);
        else
            keys[current].keys.emplace(key, line);
        const bool colour = key == "Kd" || key == "Ks" || key == "Ke" || key == "Ka";
        if (!colour && key != "Ns") return;
        if (colour && w.size() >= 2 && (w[1] == "spectral" || w[1] == "xyz")) return;  // not used by symphong
        if (w.size() < 2) throw InputError(fmt::format("{}:{}: '{}' has no value", path, line, key));
        for (std::size_t i = 1; i < w.size() && i <= 3; ++i) {
            double value;
            if (!parseFinite(w[i], value))
                throw InputError(fmt::format("{}:{}: {} value '{}' is not a finite number", path, line, key, w[i]));
            if (value < 0) throw InputError(fmt::format("{}:{}: {} value {} is negative", path, line, key, w[i]));
        }
    });
    const bool blender = mtlWrittenByBlender(text);
    for (auto& [name, material] : keys) material.file = path, material.blender = blender;
    return keys;
}

/// A map of the MTL as a TextureRef: the file (relative to the MTL's folder) through the texture table,
/// its -clamp option as the wrap mode, its -s and -o options as the coordinate map.
TextureRef mtlTexture(TextureTable& table, const std::string& dir, const std::string& name, const tinyobj::texture_option_t& opt,
                      TextureEncoding encoding, const std::string& where) {
    TextureRef ref;
    if (name.empty()) return ref;
    std::filesystem::path file = name;
    if (file.is_relative()) file = std::filesystem::path(dir) / file;
    ref.index = table.file(file.string(), encoding, where);
    if (ref.index < 0) return ref;
    ref.transform = {opt.scale[0], 0, opt.origin_offset[0], 0, opt.scale[1], opt.origin_offset[1]};
    if (!std::all_of(ref.transform.begin(), ref.transform.end(), [](double x) { return std::isfinite(x); }))
        throw InputError(fmt::format("{}: texture '{}': its -s or -o option is not finite", where, name));
    const WrapMode wrap = opt.clamp ? WrapMode::Clamp : WrapMode::Repeat;
    ref.index = table.withWrap(ref.index, wrap, wrap);
    return ref;
}

Color toColor(const tinyobj::real_t c[3]) { return {c[0], c[1], c[2]}; }

}  // namespace

namespace {

/// Positions, unit normals and texture coordinates of the OBJ's attributes.
void copyAttributes(const tinyobj::attrib_t& attrib, Scene& scene) {
    for (std::size_t i = 0; i + 2 < attrib.vertices.size(); i += 3)
        scene.positions.emplace_back(attrib.vertices[i], attrib.vertices[i + 1], attrib.vertices[i + 2]);
    for (std::size_t i = 0; i + 2 < attrib.normals.size(); i += 3) {
        Vec3 n(attrib.normals[i], attrib.normals[i + 1], attrib.normals[i + 2]);
        const double len = length(n);
        scene.normals.push_back(len > 0 ? n / len : Vec3(0, 0, 1));
    }
    for (std::size_t i = 0; i + 1 < attrib.texcoords.size(); i += 2) scene.uvs.push_back({attrib.texcoords[i], attrib.texcoords[i + 1]});
}

/// `norm` (a tangent-space normal map) and `bump`/`map_Bump` (a height map, or a normal map where
/// Blender wrote the MTL or where the image looks like one: scene/shading_normal.h), each with its -bm.
template <class Where>
void attachNormalMaps(const tinyobj::material_t& mt, const MtlMaterial& stated, TextureTable& table, const std::string& mtlDir,
                      const Where& where, Scene& scene, MaterialTextures& tx) {
    const auto multiplier = [&](const tinyobj::texture_option_t& opt, const char* key) {
        if (!std::isfinite(opt.bump_multiplier))
            throw InputError(fmt::format("{}: its -bm option '{}' is not finite", where(key), opt.bump_multiplier));
        return static_cast<double>(opt.bump_multiplier);
    };
    if (!mt.normal_texname.empty()) {
        tx.normal = mtlTexture(table, mtlDir, mt.normal_texname, mt.normal_texopt, TextureEncoding::Linear, where("norm"));
        tx.normalScale = multiplier(mt.normal_texopt, "norm");
    }
    if (mt.bump_texname.empty()) return;
    const char* key = stated.keys.count("map_Bump") ? "map_Bump" : stated.keys.count("map_bump") ? "map_bump" : "bump";
    const TextureRef ref = mtlTexture(table, mtlDir, mt.bump_texname, mt.bump_texopt, TextureEncoding::Linear, where(key));
    if (!ref.present()) return;
    const double bm = multiplier(mt.bump_texopt, key);
    if (stated.blender || looksLikeNormalMap(scene.textures[static_cast<std::size_t>(ref.index)])) {
        if (tx.normal.present()) {
            scene.warnings.push_back(fmt::format("{}: a second normal map ('{}' besides its norm map); ignored", where(key), mt.bump_texname));
            return;
        }
        tx.normal = ref;
        tx.normalScale = bm;
    } else {
        tx.bump = ref;
        tx.bumpScale = bm;
    }
}

/// One MTL material as a Phong material with its texture maps; `keys` says which keys the file gave.
PhongMaterial objMaterial(const tinyobj::material_t& mt, const MtlMaterial& stated, const std::string& path, TextureTable& table,
                          const std::string& mtlDir, Scene& scene) {
    PhongMaterial m;
    m.name = trim(mt.name);
    m.rhoD = toColor(mt.diffuse);
    m.rhoS = toColor(mt.specular);
    m.exponent = mt.shininess;
    m.emission = toColor(mt.emission);
    // A map multiplies its constant (Kd, Ks, Ns, Ke) as the MTL format says; where the file gives
    // the map but not the constant, the constant is 1 (1000 for Ns, the top of MTL's 0..1000 range).
    const auto& keys = stated.keys;
    const std::string mtlFile = stated.file.empty() ? path : stated.file;
    const auto where = [&](const char* key) {
        const auto it = keys.find(key);
        return it == keys.end() ? fmt::format("{}: material '{}'", mtlFile, m.name) : fmt::format("{}:{}", mtlFile, it->second);
    };
    MaterialTextures& tx = m.textures;
    tx.diffuse = mtlTexture(table, mtlDir, mt.diffuse_texname, mt.diffuse_texopt, TextureEncoding::Srgb, where("map_Kd"));
    tx.specular = mtlTexture(table, mtlDir, mt.specular_texname, mt.specular_texopt, TextureEncoding::Srgb, where("map_Ks"));
    tx.exponent = mtlTexture(table, mtlDir, mt.specular_highlight_texname, mt.specular_highlight_texopt, TextureEncoding::Linear,
                             where("map_Ns"));
    tx.alpha = mtlTexture(table, mtlDir, mt.alpha_texname, mt.alpha_texopt, TextureEncoding::Linear, where("map_d"));
    tx.emission = mtlTexture(table, mtlDir, mt.emissive_texname, mt.emissive_texopt, TextureEncoding::Srgb, where("map_Ke"));
    attachNormalMaps(mt, stated, table, mtlDir, where, scene, tx);
    for (const auto& [key, file] :
         {std::pair{"disp", mt.displacement_texname}, std::pair{"refl", mt.reflection_texname}, std::pair{"map_Ka", mt.ambient_texname}})
        if (!file.empty())
            scene.warnings.push_back(
                fmt::format("{}: material '{}': {} map '{}' is not supported by symphong; ignored", mtlFile, m.name, key, file));
    if (tx.diffuse.present() && !keys.count("Kd")) m.rhoD = Color(1.0);
    if (tx.specular.present() && !keys.count("Ks")) m.rhoS = Color(1.0);
    if (tx.exponent.present() && !keys.count("Ns")) m.exponent = 1000;
    if (tx.emission.present() && !keys.count("Ke")) m.emission = Color(1.0);
    if (stated.blender && !tx.specular.present() && !tx.exponent.present()) {
        // Blender's MTL: Ks = its Specular, Ns = (1 - Roughness)^2 x 1000, Pm = Metallic (scene/exporter_conventions.h).
        const double roughness = 1.0 - std::sqrt(std::clamp(mt.shininess / 1000.0, 0.0, 1.0));
        blenderPrincipledToPhong(m.rhoD, mt.metallic, mt.specular[0], roughness, m.rhoD, m.rhoS, m.exponent);
    }
    return m;
}

/// The triangles of every shape (faces of another size were split by tinyobjloader's triangulation);
/// returns whether some triangle uses the default material (index defaultIndex).
bool copyTriangles(const tinyobj::ObjReader& reader, const std::string& path, std::uint32_t defaultIndex, Scene& scene) {
    bool usedDefault = false;
    for (const tinyobj::shape_t& shape : reader.GetShapes()) {
        const tinyobj::mesh_t& mesh = shape.mesh;
        std::size_t offset = 0;
        for (std::size_t f = 0; f < mesh.num_face_vertices.size(); ++f) {
            const unsigned count = mesh.num_face_vertices[f];
            if (count != 3) {
                offset += count;
                continue;
            }
            Triangle t;
            bool allNormals = true, allUvs = true;
            for (unsigned k = 0; k < 3; ++k) {
                const tinyobj::index_t& idx = mesh.indices[offset + k];
                if (idx.vertex_index < 0 || static_cast<std::size_t>(idx.vertex_index) >= scene.positions.size() ||
                    idx.normal_index >= static_cast<int>(scene.normals.size()))
                    throw InputError(fmt::format("{}: face {} of '{}' has an index out of range", path, f + 1, shape.name));
                t.v[k] = static_cast<std::uint32_t>(idx.vertex_index);
                t.n[k] = idx.normal_index;
                t.t[k] = idx.texcoord_index;
                allNormals = allNormals && idx.normal_index >= 0;
                allUvs = allUvs && idx.texcoord_index >= 0 && static_cast<std::size_t>(idx.texcoord_index) < scene.uvs.size();
            }
            if (!allNormals) t.n = {-1, -1, -1};
            if (!allUvs) t.t = {-1, -1, -1};
            const int mid = f < mesh.material_ids.size() ? mesh.material_ids[f] : -1;
            if (mid >= 0 && static_cast<std::size_t>(mid) < defaultIndex) {
                t.material = static_cast<std::uint32_t>(mid);
            } else {
                t.material = defaultIndex;
                usedDefault = true;
            }
            scene.triangles.push_back(t);
            offset += count;
        }
    }
    return usedDefault;
}

}  // namespace

Scene loadObj(const std::string& path) {
    const std::string text = readTextFile(path);
    const ObjScan scan = validateObj(path, text);
    const std::filesystem::path dir = std::filesystem::path(path).parent_path();
    // What tinyobjloader and our scene will hold per element (bytes, generously), before either exists.
    requireMemory(scan.counts[0] * 48 + scan.counts[1] * 40 + scan.counts[2] * 48 + scan.corners * 60,
                  fmt::format("{}: a mesh of {} vertices and {} face corners", path, scan.counts[0], scan.corners));
    MtlKeys mtlKeys;
    for (const std::string& lib : scan.mtllibs) {
        const auto mtlPath = (dir / lib).string();
        if (std::filesystem::exists(mtlPath))
            for (auto& [name, material] : validateMtl(mtlPath, readTextFile(mtlPath))) mtlKeys[name] = material;
    }

    tinyobj::ObjReaderConfig config;
    config.triangulate = true;
    config.vertex_color = false;
    config.mtl_search_path = dir.string();
    tinyobj::ObjReader reader;
    if (!reader.ParseFromFile(path, config)) throw InputError(fmt::format("{}: {}", path, trim(reader.Error())));

    Scene scene;
    scene.name = std::filesystem::path(path).stem().string();
    for (const std::string& lib : scan.mtllibs)
        if (!std::filesystem::exists(dir / lib))
            scene.warnings.push_back(fmt::format("{}: material library '{}' not found; using the default material", path, lib));
    copyAttributes(reader.GetAttrib(), scene);
    TextureTable table(scene);
    for (const tinyobj::material_t& mt : reader.GetMaterials())
        scene.materials.push_back(objMaterial(mt, mtlKeys[trim(mt.name)], path, table, dir.string(), scene));
    const auto defaultIndex = static_cast<std::uint32_t>(scene.materials.size());

    std::set<std::string> undefined;
    for (const std::string& name : scan.usedMaterials)
        if (scene.findMaterial(name) < 0) undefined.insert(name);
    if (!undefined.empty()) {
        std::string list;
        for (const auto& n : undefined) list += (list.empty() ? "'" : ", '") + n + "'";
        scene.warnings.push_back(fmt::format("{}: undefined material(s) {} get the default material", path, list));
    }
    const bool usedDefault = copyTriangles(reader, path, defaultIndex, scene);
    if (usedDefault || scene.materials.empty()) {
        PhongMaterial m;  // grey diffuse
        m.name = "default";
        scene.materials.push_back(m);
    }
    if (scene.triangles.empty()) throw InputError(fmt::format("{}: no triangles in the file", path));
    if (scene.triangles.size() != scan.triangles)
        scene.warnings.push_back(fmt::format("{}: its faces make {} triangles, but {} were read: part of the geometry is missing from "
                                             "the render",
                                             path, scan.triangles, scene.triangles.size()));
    scene.camera = scene.automaticCamera();
    return scene;
}

}  // namespace symphong
