// The Scene class: a loaded scene's geometry, materials, camera, lights, environment and textures as
// Python values, its description (render/describe.h), and load_scene.
#include "io/input_error.h"
#include "python/common.h"
#include "render/describe.h"
#include "render/renderer.h"

#include <fmt/format.h>
#include <pybind11/stl.h>

#include <limits>

namespace symphong {

namespace {

int checkedSize(const char* name, long long value) {
    if (value < 1 || value > 16384) throw InputError(fmt::format("{} = {} must lie in [1, 16384]", name, value));
    return static_cast<int>(value);
}

}  // namespace

std::shared_ptr<PyScene> loadPyScene(const std::string& spec) {
    Scene scene;
    {
        py::gil_scoped_release release;  // a large OBJ takes a while; other Python threads go on
        scene = loadScene(spec);
    }
    return std::make_shared<PyScene>(std::move(scene), spec);
}

/// A Scene argument: a Scene, or a spec string loaded on the spot (its errors raised as load_scene's).
std::shared_ptr<PyScene> sceneArgument(const py::object& scene) {
    if (py::isinstance<PyScene>(scene)) return scene.cast<std::shared_ptr<PyScene>>();
    if (py::isinstance<py::str>(scene)) return loadPyScene(scene.cast<std::string>());
    throw py::type_error(fmt::format("scene: expected a symphong.Scene or a spec string, got {}",
                                     py::str(py::type::of(scene).attr("__name__")).cast<std::string>()));
}

namespace {

using PySceneClass = py::class_<PyScene, std::shared_ptr<PyScene>>;

/// Scene.mesh() and Scene.primary_hits(): the geometry as arrays.
void bindSceneArrays(PySceneClass& cls) {
    cls.def(
           "mesh",
           [](const PyScene& s) {
               const Scene& sc = s.scene();
               py::array_t<double> positions({static_cast<py::ssize_t>(sc.positions.size()), static_cast<py::ssize_t>(3)});
               double* p = positions.mutable_data();
               for (std::size_t i = 0; i < sc.positions.size(); ++i)
                   for (int c = 0; c < 3; ++c) p[3 * i + c] = sc.positions[i][c];
               py::array_t<std::uint32_t> triangles({static_cast<py::ssize_t>(sc.triangles.size()), static_cast<py::ssize_t>(3)});
               py::array_t<std::uint32_t> material(static_cast<py::ssize_t>(sc.triangles.size()));
               std::uint32_t* t = triangles.mutable_data();
               std::uint32_t* m = material.mutable_data();
               for (std::size_t i = 0; i < sc.triangles.size(); ++i) {
                   for (int c = 0; c < 3; ++c) t[3 * i + c] = sc.triangles[i].v[static_cast<std::size_t>(c)];
                   m[i] = sc.triangles[i].material;
               }
               py::dict d;
               d["positions"] = positions;
               d["triangles"] = triangles;
               d["material"] = material;
               return d;
           },
           "The geometry as rendered: dict of positions (V, 3) float64, triangles (T, 3) uint32 vertex indices (front face\n"
           "counter-clockwise: emitters emit along cross(v1 - v0, v2 - v0)) and material (T,) uint32 indices into materials.")
        .def(
            "primary_hits",
            [](const PyScene& s, long long width, long long height) {
                const int w = checkedSize("width", width), h = checkedSize("height", height);
                if (static_cast<long>(w) * h > kMaxImagePixels) throw InputError(fmt::format("image size {}x{} is too large", w, h));
                py::array_t<std::int64_t> out({static_cast<py::ssize_t>(h), static_cast<py::ssize_t>(w)});
                std::int64_t* o = out.mutable_data();
                const Accel& accel = s.accel();
                for (int y = 0; y < h; ++y)
                    for (int x = 0; x < w; ++x) {
                        Vec3 origin, dir;
                        cameraRay(s.scene().camera, w, h, x + 0.5, y + 0.5, origin, dir);
                        Hit hit;
                        o[static_cast<std::size_t>(y) * w + x] =
                            accel.intersect(origin, dir, 0.0, std::numeric_limits<double>::infinity(), hit)
                                ? static_cast<std::int64_t>(hit.prim)
                                : -1;
                    }
                return out;
            },
            py::arg("width"), py::arg("height"),
            "(H, W) int64: the triangle that the camera ray through each pixel's centre hits first (-1: none), as render()\n"
            "frames a width x height image. For masks of surfaces when comparing images region by region.");
}

/// Scene.lights, sky, environment_map, textures, has_emitter, warnings.
void bindSceneEmitters(PySceneClass& cls) {
    cls.def_property_readonly(
           "lights",
           [](const PyScene& s) {
               py::list out;
               for (const Light& l : s.scene().lights) {
                   py::dict d;
                   d["type"] = lightTypeName(l.type);
                   d["position"] = py::make_tuple(l.position.x, l.position.y, l.position.z);
                   d["direction"] = py::make_tuple(l.direction.x, l.direction.y, l.direction.z);
                   d["intensity"] = py::make_tuple(l.intensity.x, l.intensity.y, l.intensity.z);
                   d["cos_inner"] = l.cosInner;
                   d["cos_outer"] = l.cosOuter;
                   out.append(d);
               }
               return out;
           },
           "list of dicts: type (point, spot, directional), position, direction, intensity (irradiance for a directional\n"
           "light), cos_inner, cos_outer (spot cones); the default sky's sun is one")
        .def_property_readonly(
            "sky",
            [](const PyScene& s) -> py::object {
                if (!s.scene().sky) return py::none();
                const Sky& k = *s.scene().sky;
                py::dict d;
                d["zenith"] = py::make_tuple(k.zenith.x, k.zenith.y, k.zenith.z);
                d["horizon"] = py::make_tuple(k.horizon.x, k.horizon.y, k.horizon.z);
                d["ground"] = py::make_tuple(k.ground.x, k.ground.y, k.ground.z);
                d["up"] = py::make_tuple(k.up.x, k.up.y, k.up.z);
                return d;
            },
            "the default sky (dict: zenith, horizon, ground, up) when the scene brought no light of its own, else None")
        .def_property_readonly(
            "environment_map",
            [](const PyScene& s) -> py::object {
                if (!s.scene().environmentMap) return py::none();
                const EnvironmentMap& e = *s.scene().environmentMap;
                py::dict d;
                d["file"] = e.image().name();
                d["width"] = e.image().width();
                d["height"] = e.image().height();
                d["scale"] = e.scale();
                d["rotation"] = e.rotationDegrees();
                d["filter"] = std::string(filterName(e.filter()));
                return d;
            },
            "the HDR lat-long environment (dict: file, width, height, scale, rotation, filter) when the scene has one, else None")
        .def_property_readonly(
            "textures",
            [](const PyScene& s) {
                py::list out;
                for (const Texture& t : s.scene().textures) {
                    py::dict d;
                    d["file"] = t.name();
                    d["width"] = t.width();
                    d["height"] = t.height();
                    d["channels"] = t.channels();
                    d["wrap"] = py::make_tuple(std::string(wrapModeName(t.wrapU)), std::string(wrapModeName(t.wrapV)));
                    out.append(d);
                }
                return out;
            },
            "list of dicts: file, width, height, channels, wrap (u, v): the textures the materials use")
        .def_property_readonly("has_emitter", [](const PyScene& s) { return s.scene().hasEmitter(); })
        .def_property_readonly(
            "warnings", [](const PyScene& s) { return s.scene().warnings; }, "the loader's non-fatal notes");
}

}  // namespace

void registerScene(py::module_& m) {
    auto cls =
        py::class_<PyScene, std::shared_ptr<PyScene>>(m, "Scene", R"(A loaded scene: triangles with Phong materials, emitters, a camera.

Scene(spec) is load_scene(spec). The acceleration structure is built on the first render and kept.)")
            .def(py::init(&loadPyScene), py::arg("spec"))
            .def_property_readonly(
                "name", [](const PyScene& s) { return s.scene().name; }, "the scene's name (output files are named after it)")
            .def_property_readonly("spec", &PyScene::spec, "what it was loaded from: 'cornell' or the file's path")
            .def_property_readonly("triangle_count", [](const PyScene& s) { return s.scene().triangles.size(); })
            .def_property_readonly("vertex_count", [](const PyScene& s) { return s.scene().positions.size(); })
            .def_property_readonly(
                "materials",
                [](const PyScene& s) {
                    py::list out;
                    for (const PhongMaterial& mat : s.scene().materials) {
                        py::dict d;
                        d["name"] = mat.name;
                        d["rho_d"] = py::make_tuple(mat.rhoD.x, mat.rhoD.y, mat.rhoD.z);
                        d["rho_s"] = py::make_tuple(mat.rhoS.x, mat.rhoS.y, mat.rhoS.z);
                        d["n"] = mat.exponent;
                        d["emission"] = py::make_tuple(mat.emission.x, mat.emission.y, mat.emission.z);
                        out.append(d);
                    }
                    return out;
                },
                "list of dicts: name, rho_d, rho_s (RGB tuples), n (Phong exponent), emission (RGB radiance)")
            .def_property_readonly(
                "camera",
                [](const PyScene& s) {
                    const Camera& c = s.scene().camera;
                    py::dict d;
                    d["position"] = py::make_tuple(c.position.x, c.position.y, c.position.z);
                    d["target"] = py::make_tuple(c.target.x, c.target.y, c.target.z);
                    d["up"] = py::make_tuple(c.up.x, c.up.y, c.up.z);
                    d["fov_y"] = c.fovY;
                    return d;
                },
                "dict: position, target, up (tuples), fov_y (vertical field of view, degrees)")
            .def_property_readonly(
                "bounds",
                [](const PyScene& s) {
                    Vec3 lo, hi;
                    s.scene().bounds(lo, hi);
                    return py::make_tuple(py::make_tuple(lo.x, lo.y, lo.z), py::make_tuple(hi.x, hi.y, hi.z));
                },
                "((xmin, ymin, zmin), (xmax, ymax, zmax)): the axis-aligned bounding box")
            .def_property_readonly(
                "environment",
                [](const PyScene& s) {
                    const Color& e = s.scene().environment;
                    return py::make_tuple(e.x, e.y, e.z);
                },
                "RGB radiance arriving from directions that leave the scene");
    bindSceneArrays(cls);
    bindSceneEmitters(cls);
    bindFromArrays(cls);
    cls.def(
           "info", [](const PyScene& s) { return describeScene(s.scene(), s.spec()); },
           "The text `symphong info` prints for this scene: triangles, bounds, camera, materials, lights, environment,\n"
           "textures and warnings.")
        .def("__repr__", [](const PyScene& s) {
            return fmt::format("<symphong.Scene '{}' from '{}': {} triangles, {} materials>", s.scene().name, s.spec(),
                               s.scene().triangles.size(), s.scene().materials.size());
        });

    m.def("load_scene", &loadPyScene, py::arg("spec") = "cornell",
          R"(load_scene(spec='cornell') -> Scene

spec is 'cornell' (the built-in Cornell box), a Wavefront .obj file (its .mtl beside it) or a .json scene
file (docs/scene-format.md). Raises FileNotFoundError for a missing file and ValueError for any other bad
input, with the message `symphong render` prints (file, line, value). The loader's warnings are in
Scene.warnings.)");
}

}  // namespace symphong
