#include "scene/scene.h"

#include "io/files.h"
#include "io/input_error.h"
#include "scene/tangents.h"

#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <stdexcept>

namespace symphong {

void Scene::bounds(Vec3& lo, Vec3& hi) const {
    // Into locals, stored once at the end: the outputs may alias `positions` for all the compiler knows, so
    // accumulating in them went through memory at every vertex (a store, then a load that waits for it: 27 ns
    // a triangle, 1.9 ms for the 69k-triangle bunny, and a render asks up to four times).
    Vec3 l(std::numeric_limits<double>::infinity()), h(-std::numeric_limits<double>::infinity());
    for (const Triangle& t : triangles)
        for (std::uint32_t i : t.v) {
            l = vmin(l, positions[i]);
            h = vmax(h, positions[i]);
        }
    lo = l;
    hi = h;
}

int Scene::findMaterial(const std::string& n) const {
    for (std::size_t i = 0; i < materials.size(); ++i)
        if (materials[i].name == n) return static_cast<int>(i);
    return -1;
}

const char* lightTypeName(Light::Type type) {
    switch (type) {
        case Light::Type::Point:
            return "point";
        case Light::Type::Spot:
            return "spot";
        case Light::Type::Directional:
            return "directional";
    }
    return "?";
}

bool Scene::hasEmitter() const {
    if (!lights.empty()) return true;
    if (environmentMap && environmentMap->luminanceIntegral() > 0) return true;
    for (const Triangle& t : triangles)
        if (materials[t.material].isEmissive()) return true;
    return false;
}

Camera Scene::automaticCamera(double fovY) const {
    Vec3 lo, hi;
    bounds(lo, hi);
    const Vec3 center = 0.5 * (lo + hi);
    const double radius = std::max(1e-6, 0.5 * length(hi - lo));
    const double distance = radius / std::sin(0.5 * fovY * kPi / 180.0);
    // Three-quarter: 35 degrees round from +Z towards +X, 20 degrees above the horizontal.
    const double azimuth = 35.0 * kPi / 180.0, elevation = 20.0 * kPi / 180.0;
    bool emissiveTriangles = false;
    for (const Triangle& t : triangles) emissiveTriangles = emissiveTriangles || materials[t.material].isEmissive();
    const Vec3 from = emissiveTriangles
                          ? Vec3(0, 0, 1)
                          : Vec3(std::sin(azimuth) * std::cos(elevation), std::sin(elevation), std::cos(azimuth) * std::cos(elevation));
    Camera c;
    c.position = center + from * distance;
    c.target = center;
    c.up = Vec3(0, 1, 0);
    c.fovY = fovY;
    return c;
}

void finalizeScene(Scene& scene, const std::string& source, bool environmentGiven) {
    if (scene.triangles.empty()) throw InputError(fmt::format("{}: the scene has no triangles", source));
    if (scene.materials.empty()) throw InputError(fmt::format("{}: the scene has no materials", source));
    for (PhongMaterial& m : scene.materials) {
        if (!std::isfinite(m.textures.normalScale) || !std::isfinite(m.textures.bumpScale))
            throw InputError(fmt::format("{}: material '{}' has a normal or bump map strength that is not finite", source, m.name));
        try {
            if (m.textures.reflectance()) {
                // Textured: the constants are factors of the maps; rho_d + rho_s is kept <= 1 point by point
                // (scene/surface.h), so here they are only checked.
                PhongMaterial copy = m;
                validateAndClampPhong(copy);
                continue;
            }
            if (validateAndClampPhong(m))
                scene.warnings.push_back(
                    fmt::format("{}: material '{}' reflects more than it receives (Kd + Ks > 1); scaled down to Kd = ({:.3g}, {:.3g}, "
                                "{:.3g}), Ks = ({:.3g}, {:.3g}, {:.3g})",
                                source, m.name, m.rhoD.x, m.rhoD.y, m.rhoD.z, m.rhoS.x, m.rhoS.y, m.rhoS.z));
        } catch (const std::invalid_argument& e) {
            throw InputError(fmt::format("{}: {}", source, e.what()));
        }
    }
    // Embree traces in single precision: coordinates beyond 1e30 (or not finite) cannot be converted.
    constexpr double kMaxCoordinate = 1e30;
    const auto inRange = [&](const Vec3& v) {
        return isFinite(v) && std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)}) <= kMaxCoordinate;
    };
    for (std::size_t i = 0; i < scene.positions.size(); ++i)
        if (!inRange(scene.positions[i]))
            throw InputError(fmt::format("{}: vertex {} ({}, {}, {}) is not finite or beyond +-1e30", source, i, scene.positions[i].x,
                                         scene.positions[i].y, scene.positions[i].z));
    for (const Vec3& n : scene.normals)
        if (!isFinite(n)) throw InputError(fmt::format("{}: a shading normal is not finite", source));
    for (std::size_t i = 0; i < scene.lights.size(); ++i) {
        Light& l = scene.lights[i];
        if (!inRange(l.position)) throw InputError(fmt::format("{}: lights[{}] position is not finite or beyond +-1e30", source, i));
        if (!isFinite(l.position) || !isFinite(l.direction) || !isFinite(l.intensity) || minComponent(l.intensity) < 0 ||
            !std::isfinite(l.cosInner) || !std::isfinite(l.cosOuter))
            throw InputError(fmt::format("{}: lights[{}] ({}) has a non-finite or negative value", source, i, lightTypeName(l.type)));
        if (length(l.direction) == 0)
            throw InputError(fmt::format("{}: lights[{}] ({}) has a zero direction", source, i, lightTypeName(l.type)));
        l.direction = normalize(l.direction);
        if (l.type == Light::Type::Spot && !(l.cosOuter < l.cosInner))
            throw InputError(fmt::format("{}: lights[{}] (spot): the inner cone must be narrower than the outer one", source, i));
    }
    if (!isFinite(scene.environment) || minComponent(scene.environment) < 0)
        throw InputError(fmt::format("{}: environment radiance must be finite and >= 0", source));
    const Camera& c = scene.camera;
    if (!inRange(c.position) || !inRange(c.target) || !isFinite(c.up) || !std::isfinite(c.fovY))
        throw InputError(fmt::format("{}: camera has a non-finite value (or a coordinate beyond +-1e30)", source));
    if (!(c.fovY > 0 && c.fovY < 180)) throw InputError(fmt::format("{}: camera fov {} must lie in (0, 180) degrees", source, c.fovY));
    if (length(c.target - c.position) == 0) throw InputError(fmt::format("{}: camera position and target coincide", source));
    if (length(cross(c.target - c.position, c.up)) == 0)
        throw InputError(fmt::format("{}: camera up vector is parallel to the viewing direction", source));
    for (const Triangle& t : scene.triangles)
        for (std::int32_t i : t.t)
            if (i >= static_cast<std::int64_t>(scene.uvs.size()))
                throw InputError(fmt::format("{}: a texture coordinate index is out of range", source));
    for (const Tangent& t : scene.tangents)
        if (!isFinite(t.t)) throw InputError(fmt::format("{}: a tangent is not finite", source));
    for (const Triangle& t : scene.triangles)
        for (std::int32_t i : t.tg)
            if (i >= static_cast<std::int64_t>(scene.tangents.size()))
                throw InputError(fmt::format("{}: a tangent index is out of range", source));
    computeTangents(scene);  // for normal and bump maps on triangles whose file gave no tangents
    if (!scene.hasEmitter() && !environmentGiven) {
        scene.sky = Sky{};
        scene.lights.push_back(defaultSun());
        scene.warnings.push_back(
            fmt::format("{}: the scene has no light of any kind (no material with Ke > 0, no light, no environment); lighting it with "
                        "the default sky (white at the horizon, blue at the zenith, grey ground) and a sun from above the viewer's left "
                        "(irradiance 1.6). Set \"environment\" or \"lights\" in a JSON scene file to change this.",
                        source));
    }
}

bool isAssimpExtension(const std::string& path) {
    const std::string ext = lowerExtension(path);
    for (const char* e : {".gltf", ".glb", ".fbx", ".dae", ".3ds"})
        if (ext == e) return true;
    return false;
}

bool isMeshExtension(const std::string& path) {
    const std::string ext = lowerExtension(path);
    return ext == ".obj" || ext == ".ply" || isAssimpExtension(path);
}

Scene loadMeshFile(const std::string& path) {
    const std::string ext = lowerExtension(path);
    if (ext == ".obj") return loadObj(path);
    if (ext == ".ply") return loadPly(path);
    return loadAssimp(path);
}

namespace {

Scene loadSceneUnguarded(const std::string& spec) {
    if (spec == "cornell") {
        Scene s = makeCornellBox();
        finalizeScene(s, spec, false);
        return s;
    }
    if (lowerExtension(spec) == ".json") return loadJsonScene(spec);
    if (isMeshExtension(spec)) {
        Scene s = loadMeshFile(spec);
        finalizeScene(s, spec, false);
        return s;
    }
    throw InputError(fmt::format(
        "{}: unknown scene (expected 'cornell', a .obj, .gltf, .glb, .ply, .fbx, .dae or .3ds file, or a .json scene file)", spec));
}

}  // namespace

Scene loadScene(const std::string& spec) {
    // The loaders check what they can size before they allocate (io/memory.h); what still runs out of
    // memory (inside a third-party parser) is bad input too, not a crash.
    try {
        return loadSceneUnguarded(spec);
    } catch (const std::bad_alloc&) {
        throw InputError(fmt::format("{}: ran out of memory while loading it (the scene is too large for this machine)", spec));
    } catch (const std::length_error&) {
        throw InputError(fmt::format("{}: ran out of memory while loading it (a size in the file is too large)", spec));
    } catch (const std::filesystem::filesystem_error& e) {
        // A path the file names that the file system refuses (too long, a loop of links, ...).
        throw InputError(fmt::format("{}: {}: {}", spec, e.path1().string(), e.code().message()));
    }
}

}  // namespace symphong
