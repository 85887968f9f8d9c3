// python/builder.cpp — Scene.from_arrays: a scene from NumPy arrays (geometry, per-corner normals, texture
// coordinates and tangents), materials (Phong numbers, or Blender's Principled ones mapped by the loaders' own
// function, scene/exporter_conventions.h), texture maps (files or arrays), lights (as a JSON scene gives them,
// scene/json_lights.h), an environment and a camera, validated as the loaders validate files (a ValueError
// naming the array and element) and finished by the loaders' own finalizeScene. For host applications that
// have their scenes in memory: the Blender add-on (blender/symphong_blender). python/host.cpp has the rest of
// what it needs.
#include "python/builder.h"
#include "io/input_error.h"
#include "scene/json_lights.h"
#include "texture/texture_io.h"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace symphong {

namespace pybuild {

// ---------------------------------------------------------------------------------------------------
// Arrays, checked

std::string shapeText(const py::array& a) {
    std::vector<std::string> dims;
    for (py::ssize_t i = 0; i < a.ndim(); ++i) dims.push_back(std::to_string(a.shape(i)));
    return "(" + fmt::format("{}", fmt::join(dims, ", ")) + (a.ndim() == 1 ? ",)" : ")");
}

/// A float64 (N, cols) array (N,) when cols == 0; ValueError naming it for another shape or a value that is
/// not finite.
py::array_t<double, py::array::c_style> floatRows(const py::handle& obj, const std::string& name, py::ssize_t cols) {
    const py::array raw = py::array::ensure(obj);
    if (!raw) throw py::type_error(fmt::format("{}: expected an array of numbers", name));
    const char kind = raw.dtype().kind();
    if (kind != 'f' && kind != 'i' && kind != 'u')
        throw py::type_error(fmt::format("{}: expected an array of numbers, got dtype {}", name, py::str(raw.dtype()).cast<std::string>()));
    const bool ok = cols == 0 ? raw.ndim() == 1 : raw.ndim() == 2 && raw.shape(1) == cols;
    if (!ok)
        throw InputError(fmt::format("{}: expected an array of shape {}, got shape {}", name,
                                     cols == 0 ? "(N,)" : fmt::format("(N, {})", cols), shapeText(raw)));
    auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(raw);
    const double* p = a.data();
    const py::ssize_t width = cols == 0 ? 1 : cols;
    for (py::ssize_t i = 0; i < a.size(); ++i)
        if (!std::isfinite(p[i])) {
            if (cols == 0) throw InputError(fmt::format("{}[{}] = {} is not finite", name, i, p[i]));
            throw InputError(fmt::format("{}[{}, {}] = {} is not finite", name, i / width, i % width, p[i]));
        }
    return a;
}

/// An integer (N, cols) array, (N,) when cols == 0, each value in [0, limit): ValueError naming the
/// array, the element and `limitName` for one out of range.
py::array_t<std::int64_t, py::array::c_style> indexRows(const py::handle& obj, const std::string& name, py::ssize_t cols,
                                                        std::int64_t limit, const std::string& limitName) {
    const py::array raw = py::array::ensure(obj);
    if (!raw) throw py::type_error(fmt::format("{}: expected an array of integers", name));
    const char kind = raw.dtype().kind();
    if (kind != 'i' && kind != 'u' && !(raw.size() == 0 && kind == 'f'))
        throw py::type_error(
            fmt::format("{}: expected an array of integers, got dtype {}", name, py::str(raw.dtype()).cast<std::string>()));
    const bool ok = cols == 0 ? raw.ndim() == 1 : raw.ndim() == 2 && raw.shape(1) == cols;
    if (!ok)
        throw InputError(fmt::format("{}: expected an array of shape {}, got shape {}", name,
                                     cols == 0 ? "(N,)" : fmt::format("(N, {})", cols), shapeText(raw)));
    if (kind == 'u' && raw.itemsize() == 8) {  // values beyond int64 would wrap in the cast below
        const auto u = py::array_t<std::uint64_t, py::array::c_style | py::array::forcecast>::ensure(raw);
        for (py::ssize_t i = 0; i < u.size(); ++i)
            if (u.data()[i] > static_cast<std::uint64_t>(limit))
                throw InputError(fmt::format("{}: index {} is out of range", name, u.data()[i]));
    }
    auto a = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>::ensure(raw);
    const std::int64_t* p = a.data();
    const py::ssize_t width = cols == 0 ? 1 : cols;
    for (py::ssize_t i = 0; i < a.size(); ++i)
        if (p[i] < 0 || p[i] >= limit) {
            const std::string at = cols == 0 ? fmt::format("{}[{}]", name, i) : fmt::format("{}[{}, {}]", name, i / width, i % width);
            throw InputError(fmt::format("{} = {} is out of range ({} has {})", at, p[i], limitName, limit));
        }
    return a;
}

// ---------------------------------------------------------------------------------------------------
// Materials

double finiteNumber(const py::handle& v, const std::string& where) {
    if (py::isinstance<py::str>(v) || !py::hasattr(v, "__float__"))
        throw py::type_error(
            fmt::format("{}: expected a number, got {}", where, py::str(py::type::of(v).attr("__name__")).cast<std::string>()));
    const double x = v.cast<double>();
    if (!std::isfinite(x)) throw InputError(fmt::format("{} = {} is not finite", where, x));
    return x;
}

double nonNegative(const py::handle& v, const std::string& where) {
    const double x = finiteNumber(v, where);
    if (x < 0) throw InputError(fmt::format("{} = {} is negative", where, x));
    return x;
}

/// A colour: one number (grey) or three (an alpha beyond them, as Blender's RGBA sockets give it, is
/// not read); each finite and >= 0.
Color colour(const py::handle& v, const std::string& where) {
    if (py::isinstance<py::array>(v) && v.cast<py::array>().ndim() == 0) return Color(nonNegative(v.attr("item")(), where));
    if (!py::isinstance<py::str>(v) && py::hasattr(v, "__float__") && !py::isinstance<py::array>(v)) return Color(nonNegative(v, where));
    const py::sequence seq =
        py::reinterpret_borrow<py::sequence>(py::isinstance<py::array>(v) ? v.attr("tolist")() : py::reinterpret_borrow<py::object>(v));
    if (!py::isinstance<py::sequence>(seq) || py::isinstance<py::str>(seq) || (seq.size() != 3 && seq.size() != 4))
        throw InputError(fmt::format("{}: expected a number or 3 numbers (RGB), got {}", where, reprOf(v)));
    return {nonNegative(seq[0], where + "[0]"), nonNegative(seq[1], where + "[1]"), nonNegative(seq[2], where + "[2]")};
}

Vec3 vector3(const py::handle& v, const std::string& where) {
    const py::object seq = py::isinstance<py::array>(v) ? v.attr("tolist")() : py::reinterpret_borrow<py::object>(v);
    if (!py::isinstance<py::sequence>(seq) || py::isinstance<py::str>(seq) || py::len(seq) != 3)
        throw InputError(fmt::format("{}: expected 3 numbers, got {}", where, reprOf(v)));
    const py::sequence s = seq.cast<py::sequence>();
    return {finiteNumber(s[0], where + "[0]"), finiteNumber(s[1], where + "[1]"), finiteNumber(s[2], where + "[2]")};
}

}  // namespace pybuild

namespace {

using namespace pybuild;

// ---------------------------------------------------------------------------------------------------
// Python values -> JSON (lights are given as the JSON scene format gives them)

nlohmann::json toJson(const py::handle& o, const std::string& where) {
    if (o.is_none()) return nullptr;
    if (py::isinstance<py::bool_>(o)) return o.cast<bool>();
    if (py::isinstance<py::int_>(o)) return o.cast<long long>();
    if (py::isinstance<py::float_>(o)) return o.cast<double>();
    if (py::isinstance<py::str>(o)) return o.cast<std::string>();
    if (py::isinstance<py::dict>(o)) {
        nlohmann::json j = nlohmann::json::object();
        for (const auto& [k, v] : o.cast<py::dict>()) {
            const std::string key = py::str(k).cast<std::string>();
            j[key] = toJson(v, where + "." + key);
        }
        return j;
    }
    if (py::isinstance<py::array>(o) || py::isinstance<py::list>(o) || py::isinstance<py::tuple>(o)) {
        nlohmann::json j = nlohmann::json::array();
        const py::object seq = py::isinstance<py::array>(o) ? o.attr("tolist")() : py::reinterpret_borrow<py::object>(o);
        if (!py::isinstance<py::list>(seq) && !py::isinstance<py::tuple>(seq)) return toJson(seq, where);  // a 0-d array
        std::size_t i = 0;
        for (const py::handle item : seq) j.push_back(toJson(item, fmt::format("{}[{}]", where, i++)));
        return j;
    }
    if (py::hasattr(o, "__float__")) return o.cast<double>();  // NumPy scalars
    throw py::type_error(fmt::format("{}: expected a number, string, list or dict, got {}", where,
                                     py::str(py::type::of(o).attr("__name__")).cast<std::string>()));
}

// ---------------------------------------------------------------------------------------------------
// The scene

/// Per-corner attribute rows: `values` (N, cols) with `indices` (T, 3) into them, or, without indices, one
/// row per vertex (N == V) indexed as the triangles are. Returns the index of each corner (T x 3).
std::vector<std::int32_t> cornerIndices(const py::handle& indicesObj, const std::string& valuesName, const std::string& indicesName,
                                        py::ssize_t rows, const py::array_t<std::int64_t, py::array::c_style>& triangles,
                                        py::ssize_t vertexCount) {
    const auto t = static_cast<std::size_t>(triangles.shape(0));
    if (rows > std::numeric_limits<std::int32_t>::max())
        throw InputError(fmt::format("{}: {} rows is more than symphong indexes (2^31 - 1)", valuesName, rows));
    std::vector<std::int32_t> out(3 * t);
    if (indicesObj.is_none()) {
        if (rows != vertexCount)
            throw InputError(fmt::format("{}: {} rows, but positions has {} (give {} to index them per corner)", valuesName, rows,
                                         vertexCount, indicesName));
        for (std::size_t i = 0; i < 3 * t; ++i) out[i] = static_cast<std::int32_t>(triangles.data()[i]);
        return out;
    }
    const auto idx = indexRows(indicesObj, indicesName, 3, rows, valuesName + " rows");
    if (static_cast<std::size_t>(idx.shape(0)) != t)
        throw InputError(fmt::format("{}: {} rows, but triangles has {}", indicesName, idx.shape(0), t));
    for (std::size_t i = 0; i < 3 * t; ++i) out[i] = static_cast<std::int32_t>(idx.data()[i]);
    return out;
}

/// The arrays that give each corner an attribute (normals, uvs, tangents), with their index arrays.
struct CornerArrays {
    py::handle normals, normalIndices, uvs, uvIndices, tangents, tangentIndices;
};

/// Normals, texture coordinates and tangents of the triangles, per corner.
void addCornerAttributes(Scene& scene, const CornerArrays& a, const py::array_t<std::int64_t, py::array::c_style>& triangles,
                         py::ssize_t v) {
    const auto t = static_cast<std::size_t>(triangles.shape(0));
    if (!a.normals.is_none()) {
        const auto normals = floatRows(a.normals, "normals", 3);
        const std::vector<std::int32_t> corner =
            cornerIndices(a.normalIndices, "normals", "normal_indices", normals.shape(0), triangles, v);
        scene.normals.resize(static_cast<std::size_t>(normals.shape(0)));
        for (std::size_t i = 0; i < scene.normals.size(); ++i) {
            const Vec3 n{normals.data()[3 * i], normals.data()[3 * i + 1], normals.data()[3 * i + 2]};
            scene.normals[i] = length(n) > 0 ? normalize(n) : n;
        }
        // A zero normal (a degenerate face's, or a flat mesh's filler) cannot be normalised: the triangle's own is used there.
        for (std::size_t i = 0; i < t; ++i)
            for (std::size_t c = 0; c < 3; ++c) {
                const std::int32_t k = corner[3 * i + c];
                scene.triangles[i].n[c] = length(scene.normals[static_cast<std::size_t>(k)]) > 0 ? k : -1;
            }
    } else if (!a.normalIndices.is_none()) {
        throw InputError("normal_indices given without normals");
    }
    if (!a.uvs.is_none()) {
        const auto uvs = floatRows(a.uvs, "uvs", 2);
        const std::vector<std::int32_t> corner = cornerIndices(a.uvIndices, "uvs", "uv_indices", uvs.shape(0), triangles, v);
        scene.uvs.resize(static_cast<std::size_t>(uvs.shape(0)));
        for (std::size_t i = 0; i < scene.uvs.size(); ++i) scene.uvs[i] = {uvs.data()[2 * i], uvs.data()[2 * i + 1]};
        for (std::size_t i = 0; i < t; ++i)
            for (std::size_t c = 0; c < 3; ++c) scene.triangles[i].t[c] = corner[3 * i + c];
    } else if (!a.uvIndices.is_none()) {
        throw InputError("uv_indices given without uvs");
    }
    if (!a.tangents.is_none()) {
        const auto tangents = floatRows(a.tangents, "tangents", 4);
        const std::vector<std::int32_t> corner =
            cornerIndices(a.tangentIndices, "tangents", "tangent_indices", tangents.shape(0), triangles, v);
        scene.tangents.resize(static_cast<std::size_t>(tangents.shape(0)));
        for (std::size_t i = 0; i < scene.tangents.size(); ++i) {
            const double* p = tangents.data() + 4 * i;
            const Vec3 d{p[0], p[1], p[2]};
            scene.tangents[i] = {length(d) > 0 ? normalize(d) : Vec3(1, 0, 0), p[3] < 0 ? -1.0 : 1.0};
        }
        for (std::size_t i = 0; i < t; ++i)
            for (std::size_t c = 0; c < 3; ++c) scene.triangles[i].tg[c] = corner[3 * i + c];
    } else if (!a.tangentIndices.is_none()) {
        throw InputError("tangent_indices given without tangents");
    }
}

/// A file path given as a str or an os.PathLike.
bool isPath(const py::handle& o) { return py::isinstance<py::str>(o) || py::hasattr(o, "__fspath__"); }
std::string pathText(const py::handle& o) { return py::str(py::module_::import("os").attr("fspath")(o)).cast<std::string>(); }

/// environment = {map: path | image: array, scale, rotation, filter}: a lat-long image, as a JSON scene's.
EnvironmentMap environmentMap(const py::dict& e) {
    double scale = 1, rotation = 0;
    EnvironmentMap::Filter filter = EnvironmentMap::Filter::Bilinear;
    py::object image;
    for (const auto& [k, val] : e) {
        const std::string key = py::str(k).cast<std::string>();
        if (key == "map" || key == "image") {
            image = py::reinterpret_borrow<py::object>(val);
        } else if (key == "scale") {
            scale = nonNegative(val, "environment.scale");
        } else if (key == "rotation") {
            rotation = finiteNumber(val, "environment.rotation");
        } else if (key == "filter") {
            const std::string f = val.cast<std::string>();
            if (f != "bilinear" && f != "nearest")
                throw InputError(fmt::format("environment.filter '{}' is not \"bilinear\" or \"nearest\"", f));
            filter = f == "nearest" ? EnvironmentMap::Filter::Nearest : EnvironmentMap::Filter::Bilinear;
        } else {
            throw InputError(fmt::format("environment: unknown key '{}' (allowed: map, image, scale, rotation, filter)", key));
        }
    }
    if (!image) throw InputError("environment: a dict needs \"map\" (the path of a lat-long .exr or .hdr) or \"image\" (an array)");
    Texture tex;
    if (isPath(image)) {
        try {
            tex = loadTextureFile(pathText(image), TextureEncoding::Linear);
        } catch (const MissingFileError& err) {
            throw MissingFileError(fmt::format("environment.map: {}", err.what()));
        }
    } else {
        const py::array arr = py::array::ensure(image);
        if (!arr) throw py::type_error("environment.image: expected an image array");
        tex = textureFromArray(arr, TextureEncoding::Linear, "environment.image");
    }
    return EnvironmentMap(std::move(tex), scale, rotation, filter);
}

/// camera = {position, target, up, fov}, the missing keys from the automatic camera.
Camera cameraFrom(const Scene& scene, const py::handle& camera) {
    if (!py::isinstance<py::dict>(camera)) throw py::type_error("camera: expected a dict (position, target, up, fov)");
    Camera c = scene.automaticCamera();
    for (const auto& [k, val] : camera.cast<py::dict>()) {
        const std::string key = py::str(k).cast<std::string>();
        if (key == "position")
            c.position = vector3(val, "camera.position");
        else if (key == "target")
            c.target = vector3(val, "camera.target");
        else if (key == "up")
            c.up = vector3(val, "camera.up");
        else if (key == "fov")
            c.fovY = finiteNumber(val, "camera.fov");
        else
            throw InputError(fmt::format("camera: unknown key '{}' (allowed: position, target, up, fov)", key));
    }
    return c;
}

/// Positions, triangles and their materials (the materials first: the triangles' indices are checked against them).
py::array_t<std::int64_t, py::array::c_style> addGeometry(Scene& scene, const py::handle& positionsObj, const py::handle& trianglesObj,
                                                          const py::handle& materialIds, const py::handle& materials) {
    const auto positions = floatRows(positionsObj, "positions", 3);
    const py::ssize_t v = positions.shape(0);
    if (v > std::numeric_limits<std::uint32_t>::max()) throw InputError("positions: more than 2^32 - 1 vertices");
    auto triangles = indexRows(trianglesObj, "triangles", 3, v, "positions");
    const auto t = static_cast<std::size_t>(triangles.shape(0));
    {
        TextureTable table(scene);
        if (!materials.is_none())
            for (const py::handle m : materials) scene.materials.push_back(material(m, scene.materials.size(), table));
        if (scene.materials.empty()) scene.materials.push_back(PhongMaterial{});  // as an OBJ without MTL: rho_d 0.7
    }
    std::vector<std::int64_t> mat(t, 0);
    if (!materialIds.is_none()) {
        const auto ids = indexRows(materialIds, "material_ids", 0, static_cast<std::int64_t>(scene.materials.size()), "materials");
        if (static_cast<std::size_t>(ids.shape(0)) != t)
            throw InputError(fmt::format("material_ids: {} entries, but triangles has {}", ids.shape(0), t));
        std::copy(ids.data(), ids.data() + t, mat.begin());
    }
    scene.positions.resize(static_cast<std::size_t>(v));
    for (std::size_t i = 0; i < scene.positions.size(); ++i)
        scene.positions[i] = {positions.data()[3 * i], positions.data()[3 * i + 1], positions.data()[3 * i + 2]};
    scene.triangles.resize(t);
    for (std::size_t i = 0; i < t; ++i) {
        Triangle& tri = scene.triangles[i];
        for (std::size_t c = 0; c < 3; ++c) tri.v[c] = static_cast<std::uint32_t>(triangles.data()[3 * i + c]);
        tri.material = static_cast<std::uint32_t>(mat[i]);
    }
    return triangles;
}

std::shared_ptr<PyScene> fromArrays(const py::handle& positions, const py::handle& trianglesObj, const py::handle& materialIds,
                                    const CornerArrays& corners, const py::handle& materials, const py::handle& lights,
                                    const py::handle& environment, const py::handle& camera, const std::string& name) {
    Scene scene;
    scene.name = name;
    const auto triangles = addGeometry(scene, positions, trianglesObj, materialIds, materials);
    addCornerAttributes(scene, corners, triangles, static_cast<py::ssize_t>(scene.positions.size()));
    if (!lights.is_none()) {
        std::size_t i = 0;
        for (const py::handle l : lights) {
            const std::string where = fmt::format("lights[{}]", i++);
            addJsonLight(scene, toJson(l, where), where, name);
        }
    }
    const bool environmentGiven = !environment.is_none();
    if (py::isinstance<py::dict>(environment))
        scene.environmentMap.emplace(environmentMap(environment.cast<py::dict>()));
    else if (environmentGiven)
        scene.environment = colour(environment, "environment");
    // After the lights and materials: the automatic camera depends on whether anything emits.
    scene.camera = camera.is_none() ? scene.automaticCamera() : cameraFrom(scene, camera);
    finalizeScene(scene, name, environmentGiven);
    return std::make_shared<PyScene>(std::move(scene), name);
}

const char* const kFromArraysDoc = R"doc(Scene.from_arrays(positions, triangles, *, material_ids=None, normals=None, normal_indices=None,
                  uvs=None, uv_indices=None, tangents=None, tangent_indices=None, materials=None, lights=None,
                  environment=None, camera=None, name='arrays') -> Scene

A scene from NumPy arrays, without a file: what an OBJ or JSON scene file would give, checked as the loaders
check files (ValueError naming the array and element: "triangles[5, 2] = 99 is out of range (positions has 8)",
"positions[3, 1] = nan is not finite", "normals: expected an array of shape (N, 3), got shape (4, 2)").

positions      (V, 3) numbers: the vertices
triangles      (T, 3) integers in [0, V): counter-clockwise seen from the front (emitters emit to the front)
material_ids   (T,) integers into materials (default: every triangle material 0)
normals        (N, 3) shading normals; with normal_indices (T, 3) into them per corner, else one per vertex (N = V)
uvs            (N, 2) texture coordinates (u right, v up); uv_indices (T, 3) as for normals
tangents       (N, 4) tangent xyz and the bitangent's sign w (bitangent = w cross(n, t)); tangent_indices as for
               normals. Without them, triangles with a normal or bump map get computed tangents as files do.
materials      list of dicts. Phong: rho_d, rho_s (one number or RGB), n, diffuse_texture, specular_texture,
               exponent_texture. Or Blender's Principled BSDF: base_color, metallic, specular (default 0.5),
               roughness (default 0.5), base_color_texture, metallic_roughness_texture (G roughness, B metallic),
               mapped as the glTF/FBX readers map them (principled_to_phong). Both: name, emission (radiance),
               emission_texture, alpha_texture (cut-out), normal_texture with normal_scale, bump_texture with
               bump_scale. A texture is a file path, an image array ((H, W) or (H, W, C), row 0 at the top; uint8
               colour maps are sRGB-decoded as 8-bit files are, floats are linear) or a dict {image, wrap, srgb,
               transform}. Default: one material, rho_d 0.7.
lights         list of dicts as a JSON scene's "lights" (docs/scene-format.md#lights): point, spot, directional, quad
environment    a radiance (number or RGB), or a dict {map: path | image: (H, W, 3) float array, scale, rotation,
               filter}: a lat-long image as a JSON scene's. None: none given (a scene with no light at all then gets
               the default sky, with a warning, as a file does).
camera         dict: position, target, up, fov (vertical, degrees); missing keys from the automatic camera.
)doc";

}  // namespace

void bindFromArrays(py::class_<PyScene, std::shared_ptr<PyScene>>& cls) {
    cls.def_static(
        "from_arrays",
        [](const py::object& positions, const py::object& triangles, const py::object& materialIds, const py::object& normals,
           const py::object& normalIndices, const py::object& uvs, const py::object& uvIndices, const py::object& tangents,
           const py::object& tangentIndices, const py::object& materials, const py::object& lights, const py::object& environment,
           const py::object& camera, const std::string& name) {
            return fromArrays(positions, triangles, materialIds,
                              CornerArrays{normals, normalIndices, uvs, uvIndices, tangents, tangentIndices}, materials, lights,
                              environment, camera, name);
        },
        py::arg("positions"), py::arg("triangles"), py::kw_only(), py::arg("material_ids") = py::none(), py::arg("normals") = py::none(),
        py::arg("normal_indices") = py::none(), py::arg("uvs") = py::none(), py::arg("uv_indices") = py::none(),
        py::arg("tangents") = py::none(), py::arg("tangent_indices") = py::none(), py::arg("materials") = py::none(),
        py::arg("lights") = py::none(), py::arg("environment") = py::none(), py::arg("camera") = py::none(), py::arg("name") = "arrays",
        kFromArraysDoc);
}

}  // namespace symphong