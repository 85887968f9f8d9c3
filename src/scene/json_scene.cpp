// JSON scene files: an OBJ (or the built-in Cornell box) plus a camera, material overrides and an
// environment radiance. The format is documented in docs/scene-format.md. Unknown keys are errors, so
// a typo never silently falls back to a default.
#include "io/files.h"
#include "io/input_error.h"
#include "scene/json_lights.h"
#include "scene/scene.h"
#include "texture/texture_io.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <set>

namespace symphong {

namespace {

using nlohmann::json;

/// A value for a message: its JSON text, cut at 60 characters (a huge or deeply nested value would
/// make a huge message; the document's depth is limited before any of this runs).
std::string brief(const json& j) {
    std::string text = j.dump();
    if (text.size() > 60) text = text.substr(0, 57) + "...";
    return text;
}

/// The deepest nesting of arrays and objects in j, found without recursion.
std::size_t nestingDepth(const json& root) {
    std::size_t deepest = 0;
    std::vector<std::pair<const json*, std::size_t>> stack{{&root, 0}};
    while (!stack.empty()) {
        const auto [j, depth] = stack.back();
        stack.pop_back();
        deepest = std::max(deepest, depth);
        if (j->is_structured())
            for (const json& child : *j) stack.emplace_back(&child, depth + 1);
    }
    return deepest;
}

void checkKeys(const json& obj, const std::set<std::string>& allowed, const std::string& where, const std::string& path) {
    if (!obj.is_object()) throw InputError(fmt::format("{}: {} must be a JSON object", path, where));
    for (const auto& item : obj.items())
        if (!allowed.count(item.key())) {
            std::string list;
            for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
            throw InputError(fmt::format("{}: unknown key '{}' in {} (allowed: {})", path, item.key(), where, list));
        }
}

double number(const json& j, const std::string& where, const std::string& path) {
    if (!j.is_number()) throw InputError(fmt::format("{}: {} must be a number, got {}", path, where, brief(j)));
    const double v = j.get<double>();
    if (!std::isfinite(v)) throw InputError(fmt::format("{}: {} is not finite", path, where));
    return v;
}

Vec3 vec3(const json& j, const std::string& where, const std::string& path) {
    if (j.is_number()) {
        const double v = number(j, where, path);
        return Vec3(v);
    }
    if (!j.is_array() || j.size() != 3)
        throw InputError(fmt::format("{}: {} must be an array of 3 numbers, got {}", path, where, brief(j)));
    return {number(j[0], where, path), number(j[1], where, path), number(j[2], where, path)};
}

Color nonNegativeColor(const json& j, const std::string& where, const std::string& path) {
    const Color c = vec3(j, where, path);
    if (minComponent(c) < 0) throw InputError(fmt::format("{}: {} has a negative value {}", path, where, brief(j)));
    return c;
}

constexpr double kDegree = 3.14159265358979323846 / 180.0;

}  // namespace

void addJsonLight(Scene& scene, const json& j, const std::string& where, const std::string& path) {
    if (!j.is_object() || !j.contains("type") || !j["type"].is_string())
        throw InputError(fmt::format("{}: {} must be an object with a \"type\": point, spot, directional or quad", path, where));
    const std::string type = j["type"].get<std::string>();
    Light light;
    if (type == "point") {
        checkKeys(j, {"type", "position", "intensity"}, where, path);
        light.type = Light::Type::Point;
    } else if (type == "spot") {
        checkKeys(j, {"type", "position", "direction", "target", "intensity", "angle", "inner"}, where, path);
        light.type = Light::Type::Spot;
        if (j.contains("direction") == j.contains("target"))
            throw InputError(fmt::format("{}: {} (spot) needs exactly one of \"direction\" and \"target\"", path, where));
        const double outer = j.contains("angle") ? number(j["angle"], where + ".angle", path) : 30.0;
        if (!(outer > 0 && outer <= 90)) throw InputError(fmt::format("{}: {}.angle = {} must lie in (0, 90] degrees", path, where, outer));
        const double inner = j.contains("inner") ? number(j["inner"], where + ".inner", path) : std::max(0.0, outer - 5.0);
        if (!(inner >= 0 && inner < outer))
            throw InputError(fmt::format("{}: {}.inner = {} must lie in [0, angle) = [0, {}) degrees", path, where, inner, outer));
        light.cosOuter = std::cos(outer * kDegree);
        light.cosInner = std::cos(inner * kDegree);
    } else if (type == "directional") {
        checkKeys(j, {"type", "direction", "irradiance"}, where, path);
        light.type = Light::Type::Directional;
    } else if (type == "quad") {
        checkKeys(j, {"type", "corner", "edge1", "edge2", "radiance"}, where, path);
        for (const char* key : {"corner", "edge1", "edge2", "radiance"})
            if (!j.contains(key)) throw InputError(fmt::format("{}: {} (quad) needs \"{}\"", path, where, key));
        const Vec3 c = vec3(j["corner"], where + ".corner", path), e1 = vec3(j["edge1"], where + ".edge1", path),
                   e2 = vec3(j["edge2"], where + ".edge2", path);
        if (length(cross(e1, e2)) == 0) throw InputError(fmt::format("{}: {} (quad): edge1 and edge2 span no area", path, where));
        PhongMaterial m;
        m.name = where;
        m.rhoD = Color(0.0);
        m.emission = nonNegativeColor(j["radiance"], where + ".radiance", path);
        scene.materials.push_back(m);
        const auto material = static_cast<std::uint32_t>(scene.materials.size() - 1);
        const auto base = static_cast<std::uint32_t>(scene.positions.size());
        for (const Vec3& v : {c, c + e1, c + e1 + e2, c + e2}) scene.positions.push_back(v);
        scene.triangles.push_back({{base, base + 1, base + 2}, {-1, -1, -1}, material});
        scene.triangles.push_back({{base, base + 2, base + 3}, {-1, -1, -1}, material});
        return;
    } else {
        throw InputError(fmt::format("{}: {}.type '{}' is not a light type (valid: point, spot, directional, quad)", path, where, type));
    }
    const bool directional = light.type == Light::Type::Directional;
    const char* power = directional ? "irradiance" : "intensity";
    if (!j.contains(power)) throw InputError(fmt::format("{}: {} ({}) needs \"{}\"", path, where, type, power));
    light.intensity = nonNegativeColor(j[power], where + "." + power, path);
    if (!directional) {
        if (!j.contains("position")) throw InputError(fmt::format("{}: {} ({}) needs \"position\"", path, where, type));
        light.position = vec3(j["position"], where + ".position", path);
    }
    if (directional || light.type == Light::Type::Spot) {
        if (j.contains("target"))
            light.direction = vec3(j["target"], where + ".target", path) - light.position;
        else if (j.contains("direction"))
            light.direction = vec3(j["direction"], where + ".direction", path);
        else
            throw InputError(fmt::format("{}: {} ({}) needs \"direction\"", path, where, type));
        if (length(light.direction) == 0) throw InputError(fmt::format("{}: {}: the direction is zero", path, where));
        light.direction = normalize(light.direction);
    }
    scene.lights.push_back(light);
}

namespace {

/// "environment": {"map": file, "scale", "rotation", "filter"}: an HDR lat-long image
/// (scene/environment_map.h), its file relative to the scene file's folder.
EnvironmentMap environmentMap(const json& e, const std::filesystem::path& dir, const std::string& path) {
    checkKeys(e, {"map", "scale", "rotation", "filter"}, "\"environment\"", path);
    if (!e.contains("map") || !e["map"].is_string())
        throw InputError(fmt::format("{}: environment.map must be the path of a lat-long image (.exr or .hdr)", path));
    std::filesystem::path file = e["map"].get<std::string>();
    if (file.is_relative()) file = dir / file;
    const double scale = e.contains("scale") ? number(e["scale"], "environment.scale", path) : 1.0;
    if (scale < 0) throw InputError(fmt::format("{}: environment.scale = {} is negative", path, scale));
    const double rotation = e.contains("rotation") ? number(e["rotation"], "environment.rotation", path) : 0.0;
    EnvironmentMap::Filter filter = EnvironmentMap::Filter::Bilinear;
    if (e.contains("filter")) {
        if (e["filter"] == "nearest")
            filter = EnvironmentMap::Filter::Nearest;
        else if (e["filter"] != "bilinear")
            throw InputError(fmt::format("{}: environment.filter {} is not \"bilinear\" or \"nearest\"", path, brief(e["filter"])));
    }
    try {
        return EnvironmentMap(loadTextureFile(file.string(), TextureEncoding::Linear), scale, rotation, filter);
    } catch (const MissingFileError& err) {
        throw MissingFileError(fmt::format("{}: environment.map: {}", path, err.what()));
    } catch (const InputError& err) {
        throw InputError(fmt::format("{}: environment.map: {}", path, err.what()));
    }
}

}  // namespace

namespace {

/// The document, or an InputError naming the file, line and column of a syntax error.
json parseSceneJson(const std::string& path) {
    const std::string text = readTextFile(path);
    json doc;
    try {
        doc = json::parse(text);
    } catch (const json::parse_error& e) {
        // file:line:column from the byte offset nlohmann reports (1-based; the byte just read), then its
        // message without the "[json.exception...] parse error at line L, column C: " prefix.
        const std::size_t byte = std::min<std::size_t>(e.byte > 0 ? e.byte - 1 : 0, text.size());
        std::size_t line = 1, lineStart = 0;
        for (std::size_t i = 0; i < byte; ++i)
            if (text[i] == '\n') {
                ++line;
                lineStart = i + 1;
            }
        std::string what = e.what();
        if (const auto colon = what.find(": "); colon != std::string::npos) what = what.substr(colon + 2);
        throw InputError(fmt::format("{}:{}:{}: malformed JSON: {}", path, line, byte - lineStart + 1, what));
    } catch (const json::exception& e) {
        // Not a syntax error but a value nlohmann cannot hold (a number beyond double, e.g. 1e400).
        std::string what = e.what();
        if (const auto bracket = what.find("] "); bracket != std::string::npos) what = what.substr(bracket + 2);
        throw InputError(fmt::format("{}: malformed JSON: {}", path, what));
    }
    // Deeper than any scene needs; also keeps every recursive walk of the document (dump) shallow.
    constexpr std::size_t kMaxDepth = 32;
    if (nestingDepth(doc) > kMaxDepth) throw InputError(fmt::format("{}: JSON nested deeper than {} levels", path, kMaxDepth));
    return doc;
}

/// The scene's geometry: "obj" or "mesh" (a file) or "builtin"; `cameraFromData` says whether its camera
/// is the data's own (a mesh file's or the built-in box's) rather than the automatic one.
Scene loadGeometry(const json& doc, const std::filesystem::path& dir, const std::string& path, bool& cameraFromData) {
    if (doc.contains("obj") + doc.contains("mesh") + doc.contains("builtin") != 1)
        throw InputError(fmt::format("{}: give exactly one of \"obj\" or \"mesh\" (a path) or \"builtin\": \"cornell\"", path));
    if (doc.contains("builtin")) {
        if (doc["builtin"] != "cornell")
            throw InputError(fmt::format("{}: unknown builtin scene {} (valid: \"cornell\")", path, brief(doc["builtin"])));
        cameraFromData = true;
        return makeCornellBox();
    }
    const char* key = doc.contains("obj") ? "obj" : "mesh";
    if (!doc[key].is_string()) throw InputError(fmt::format("{}: \"{}\" must be a string path", path, key));
    std::filesystem::path file = doc[key].get<std::string>();
    if (file.is_relative()) file = dir / file;
    const std::string ext = lowerExtension(file.string());
    if (std::string(key) == "mesh" && !isMeshExtension(file.string()))
        throw InputError(
            fmt::format("{}: \"mesh\": {}: not a format symphong reads (.obj, .gltf, .glb, .ply, .fbx, .dae, .3ds)", path, file.string()));
    try {
        // A camera from the file (glTF, FBX, Collada) is the scene's own, as the built-in box's.
        cameraFromData = ext != ".obj" && ext != ".ply";
        return loadMeshFile(file.string());
    } catch (const MissingFileError& e) {
        throw MissingFileError(fmt::format("{}: \"{}\": {}", path, key, e.what()));
    } catch (const InputError& e) {
        throw InputError(fmt::format("{}: \"{}\": {}", path, key, e.what()));
    }
}

/// "materials": overrides of the named materials' kd, ks, ns, ke.
void overrideMaterials(Scene& scene, const json& mats, const std::string& path) {
    if (!mats.is_object()) throw InputError(fmt::format("{}: \"materials\" must be an object of name: {{...}}", path));
    for (const auto& item : mats.items()) {
        const int idx = scene.findMaterial(item.key());
        if (idx < 0) {
            std::string list;
            for (const auto& m : scene.materials) list += (list.empty() ? "" : ", ") + m.name;
            throw InputError(fmt::format("{}: material override '{}' matches no material in the scene (have: {})", path, item.key(), list));
        }
        const json& m = item.value();
        const std::string where = "materials." + item.key();
        checkKeys(m, {"kd", "ks", "ns", "ke"}, where, path);
        PhongMaterial& mat = scene.materials[static_cast<std::size_t>(idx)];
        if (m.contains("kd")) mat.rhoD = nonNegativeColor(m["kd"], where + ".kd", path);
        if (m.contains("ks")) mat.rhoS = nonNegativeColor(m["ks"], where + ".ks", path);
        if (m.contains("ke")) mat.emission = nonNegativeColor(m["ke"], where + ".ke", path);
        if (m.contains("ns")) {
            mat.exponent = number(m["ns"], where + ".ns", path);
            if (mat.exponent < 0)
                throw InputError(fmt::format("{}: {}.ns = {} is negative (a Phong exponent must be >= 0)", path, where, mat.exponent));
        }
    }
}

/// "camera": position, target, up, fov over the data's camera or the automatic one.
Camera sceneCamera(const Scene& scene, const json& c, bool cameraFromData, const std::string& path) {
    checkKeys(c, {"position", "target", "up", "fov"}, "\"camera\"", path);
    Camera cam = cameraFromData ? scene.camera : scene.automaticCamera();
    if (c.contains("position")) cam.position = vec3(c["position"], "camera.position", path);
    if (c.contains("target")) cam.target = vec3(c["target"], "camera.target", path);
    if (c.contains("up")) cam.up = vec3(c["up"], "camera.up", path);
    if (c.contains("fov")) cam.fovY = number(c["fov"], "camera.fov", path);
    return cam;
}

}  // namespace

Scene loadJsonScene(const std::string& path) {
    const json doc = parseSceneJson(path);
    checkKeys(doc, {"obj", "mesh", "builtin", "camera", "materials", "environment", "name", "lights", "render"}, "the scene", path);
    const std::filesystem::path dir = std::filesystem::path(path).parent_path();
    bool cameraFromData = false;
    Scene scene = loadGeometry(doc, dir, path, cameraFromData);
    scene.name = std::filesystem::path(path).stem().string();
    if (doc.contains("name")) {
        if (!doc["name"].is_string()) throw InputError(fmt::format("{}: \"name\" must be a string", path));
        scene.name = doc["name"].get<std::string>();
    }
    if (doc.contains("lights")) {
        if (!doc["lights"].is_array()) throw InputError(fmt::format("{}: \"lights\" must be an array of lights", path));
        for (std::size_t i = 0; i < doc["lights"].size(); ++i) addJsonLight(scene, doc["lights"][i], fmt::format("lights[{}]", i), path);
    }
    if (doc.contains("materials")) overrideMaterials(scene, doc["materials"], path);
    // After the lights and materials: the automatic camera depends on whether anything emits.
    if (doc.contains("camera")) scene.camera = sceneCamera(scene, doc["camera"], cameraFromData, path);
    const bool environmentGiven = doc.contains("environment");
    if (environmentGiven) {
        const json& e = doc["environment"];
        if (e.is_object())
            scene.environmentMap.emplace(environmentMap(e, dir, path));
        else
            scene.environment = nonNegativeColor(e, "environment", path);
    }
    if (doc.contains("render")) {
        if (!doc["render"].is_object()) throw InputError(fmt::format("{}: \"render\" must be an object of render settings", path));
        scene.renderSettings = doc["render"].dump();
    }
    finalizeScene(scene, path, environmentGiven);
    return scene;
}

}  // namespace symphong
