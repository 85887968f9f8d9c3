// python/common.h — what the module's files share: the Scene object (a loaded scene and its lazily built
// acceleration structure), running work with the GIL released and Ctrl-C watched, and the image <-> NumPy
// conversions. Each file registers its part of the module (scene.cpp, render.cpp, study.cpp, arrays.cpp;
// module.cpp puts them together).
#pragma once

#include "accel/accel.h"
#include "io/image.h"
#include "scene/scene.h"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

namespace symphong {

namespace py = pybind11;

/// A loaded scene and, built on its first render, its Embree acceleration structure, shared by every
/// later render of it.
class PyScene {
public:
    PyScene(Scene scene, std::string spec) : scene_(std::move(scene)), spec_(std::move(spec)) {}

    const Scene& scene() const { return scene_; }
    const std::string& spec() const { return spec_; }
    /// Thread-safe: called without the GIL by concurrent renders.
    const Accel& accel() const {
        std::call_once(accelOnce_, [this] { accel_ = std::make_unique<Accel>(scene_); });
        return *accel_;
    }

private:
    Scene scene_;
    std::string spec_;
    mutable std::once_flag accelOnce_;
    mutable std::unique_ptr<Accel> accel_;
};

/// load_scene(spec): loads with the GIL released.
std::shared_ptr<PyScene> loadPyScene(const std::string& spec);

/// A Scene argument: a Scene, or a spec string loaded on the spot (its errors raised as load_scene's).
std::shared_ptr<PyScene> sceneArgument(const py::object& scene);

/// (H, W, 3) float32 copy of an image: the values the EXR writer stores, bit for bit.
py::array_t<float> toArray(const Image& img);
/// An image from an (H, W, 3) or (H, W) numeric array; InputError for any other shape or a non-finite value.
Image fromArray(const py::array& input);

/// The text of a Python object's repr.
inline std::string reprOf(const py::handle& o) { return py::repr(o).cast<std::string>(); }

/// Runs `work(cancel)` on a worker thread with the GIL released while this thread watches for Python
/// signals. On Ctrl-C (or any signal handler that raises) it sets `cancel`, waits for the work to stop
/// (a render stops after its current tiles) and raises the handler's exception, KeyboardInterrupt.
/// Exceptions of the work are rethrown here, where pybind11 translates them.
template <class Work>
auto runInterruptible(Work&& work) -> decltype(work(std::declval<const std::atomic<bool>&>())) {
    using Result = decltype(work(std::declval<const std::atomic<bool>&>()));
    std::atomic<bool> cancel{false};
    std::optional<Result> result;
    std::exception_ptr error;
    bool interrupted = false;
    {
        py::gil_scoped_release release;
        std::mutex m;
        std::condition_variable cv;
        bool finished = false;
        std::thread worker([&] {
            try {
                result.emplace(work(cancel));
            } catch (...) {
                error = std::current_exception();
            }
            std::lock_guard lock(m);
            finished = true;
            cv.notify_all();
        });
        std::unique_lock lock(m);
        while (!finished) {
            cv.wait_for(lock, std::chrono::milliseconds(20));
            if (finished || interrupted) continue;
            lock.unlock();
            {
                py::gil_scoped_acquire gil;
                // Signal handlers run here, on the main thread only; a pending KeyboardInterrupt stays set.
                if (PyErr_CheckSignals() != 0) interrupted = true;
            }
            if (interrupted) cancel.store(true);
            lock.lock();
        }
        lock.unlock();
        worker.join();
    }
    if (interrupted) throw py::error_already_set();
    if (error) std::rethrow_exception(error);
    return std::move(*result);
}

/// A keyword argument that is the module's own, not a setting of a schema: taken out of `kwargs`
/// (`fallback` when absent).
inline py::object takeKeyword(py::dict& kwargs, const char* key, py::object fallback) {
    if (!kwargs.contains(key)) return fallback;
    py::object v = kwargs[key];
    PyDict_DelItemString(kwargs.ptr(), key);
    return v;
}

/// The `progress` keyword taken out of `kwargs`: whether to draw a progress bar (None or absent: when
/// stderr is a terminal).
bool takeProgress(py::dict& kwargs);

void registerScene(py::module_& m);
void registerRender(py::module_& m);
void registerStudy(py::module_& m);
void registerCompare(py::module_& m);
void registerArrays(py::module_& m);
/// principled_to_phong, render_settings, Progressive (python/host.cpp).
void registerHost(py::module_& m);
/// Scene.from_arrays (python/builder.cpp).
void bindFromArrays(py::class_<PyScene, std::shared_ptr<PyScene>>& cls);

}  // namespace symphong
