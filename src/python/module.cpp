// python/ — the `symphong` Python module (pybind11): scenes, renders, the furnace and studies from
// Python, images as NumPy arrays. A second front end beside cli/, at the same level: it takes keyword
// arguments through the same settings schemas as the command line (python/schema_py.h), runs them with
// the GIL released (Ctrl-C cancels within a tile), and turns InputError into ValueError
// (FileNotFoundError for a missing file) with the command line's message. It holds no rendering logic;
// docs/python.md is its guide. Files: scene.cpp (Scene, load_scene), render.cpp, study.cpp (furnace,
// study), arrays.cpp (NumPy images), builder.cpp and builder_materials.cpp (scenes from arrays), host.cpp
// (the Principled mapping, the settings schema as data, renders pass by pass: for the Blender add-on), this
// one (the module and its errors).
#include "io/input_error.h"
#include "python/common.h"

namespace symphong {
namespace {

const char* const kModuleDoc = R"(symphong: a Phong path tracer built to compare Monte Carlo estimators, symmetric sampling among them.

    scene = symphong.load_scene('cornell')            # or an .obj / .json file
    image, stats = symphong.render(scene, spp=16)     # float32 (H, W, 3) linear radiance
    symphong.write_image('cornell.png', image)

symphong.compare(test, reference) measures an image (a file or an array) against a reference, as `symphong compare`.

render, furnace, study and compare take the command line's options as keyword arguments with the same defaults
(--max-depth is max_depth, and so on) and give the same numbers: render's image is bit for bit the EXR
that `symphong render` writes with the same settings, at any thread count. Bad input raises ValueError
(FileNotFoundError for a missing file) with the command line's message. Renders, furnaces and studies run
with the GIL released; Ctrl-C raises KeyboardInterrupt within a tile's time. Guide: docs/python.md.)";

}  // namespace
}  // namespace symphong

PYBIND11_MODULE(symphong, m) {
    using namespace symphong;
    m.doc() = kModuleDoc;
    m.attr("__version__") = SYMPHONG_VERSION;

    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const MissingFileError& e) {
            PyErr_SetString(PyExc_FileNotFoundError, e.what());
        } catch (const InputError& e) {
            PyErr_SetString(PyExc_ValueError, e.what());
        }
    });

    registerScene(m);
    registerRender(m);
    registerStudy(m);
    registerCompare(m);
    registerArrays(m);
    registerHost(m);
}
