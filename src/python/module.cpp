// python/ — the `symphong` Python module (pybind11): scenes, renders, the furnace and studies from
// Python, images as NumPy arrays. A second front end beside cli/, at the same level: it turns Python
// arguments into the settings the layers below take, runs them with the GIL released (Ctrl-C cancels
// within a tile), and turns InputError into ValueError (FileNotFoundError for a missing file) with the
// command line's message. It holds no rendering logic; docs/python.md is its guide.
#include "accel/accel.h"
#include "estimators/estimator.h"
#include "io/files.h"
#include "io/image.h"
#include "io/input_error.h"
#include "render/progress.h"
#include "render/renderer.h"
#include "sampling/sampler.h"
#include "scene/scene.h"
#include "study/furnace.h"
#include "study/study.h"

#include <fmt/format.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <filesystem>
#include <memory>
#include <mutex>
#include <limits>
#include <optional>
#include <thread>

namespace py = pybind11;

namespace symphong {
namespace {

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

std::shared_ptr<PyScene> loadPyScene(const std::string& spec) {
    Scene scene;
    {
        py::gil_scoped_release release;  // a large OBJ takes a while; other Python threads go on
        scene = loadScene(spec);
    }
    return std::make_shared<PyScene>(std::move(scene), spec);
}

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

// ---- argument checks: ValueError naming the keyword argument ----

template <class T>
T checkedRange(const char* name, long long value, long long lo, long long hi) {
    if (value < lo || value > hi) throw InputError(fmt::format("{} = {} must lie in [{}, {}]", name, value, lo, hi));
    return static_cast<T>(value);
}

std::uint64_t checkedSeed(const py::int_& seed) {
    const py::int_ zero(0), limit = py::int_(py::reinterpret_steal<py::object>(PyLong_FromUnsignedLongLong(~0ULL)));
    if (seed < zero || seed > limit) throw InputError(fmt::format("seed = {} must lie in [0, 2**64 - 1]", py::repr(seed).cast<std::string>()));
    return seed.cast<std::uint64_t>();
}

/// A list of names from "a,b,c", "all" or a sequence of strings.
std::vector<std::string> nameList(const py::object& value, const std::vector<std::string>& all) {
    std::vector<std::string> out;
    if (py::isinstance<py::str>(value)) {
        const std::string text = value.cast<std::string>();
        if (text == "all") return all;
        std::size_t start = 0;
        while (true) {
            const std::size_t comma = text.find(',', start);
            out.push_back(text.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
            if (comma == std::string::npos) break;
            start = comma + 1;
        }
        return out;
    }
    for (const py::handle item : value) out.push_back(py::cast<std::string>(item));
    return out;
}

/// One number or a sequence of numbers.
template <class T>
std::vector<T> numberList(const py::object& value) {
    if (py::isinstance<py::str>(value)) throw py::type_error("expected a number or a sequence of numbers, got a string");
    if (py::hasattr(value, "__iter__")) {
        std::vector<T> out;
        for (const py::handle item : value) out.push_back(py::cast<T>(item));
        return out;
    }
    return {value.cast<T>()};
}

EstimatorOptions estimatorOptions(int symmetricN, bool paperRefined, const std::string& mode, int orbit = 2) {
    EstimatorOptions o;
    o.symmetricN = checkedRange<int>("symmetric_n", symmetricN, 1, 4096);
    if (orbit != 1 && orbit != 2 && orbit != 4 && orbit != 8)
        throw InputError(fmt::format("symmetric_orbit: {} is not one of 1, 2, 4, 8", orbit));
    o.symmetricOrbit = orbit;
    o.paperRefined = paperRefined;
    try {
        o.symmetricMode = parseSymmetricMode(mode);
    } catch (const std::invalid_argument& e) {
        throw InputError(fmt::format("symmetric_mode: {}", e.what()));
    }
    return o;
}

// ---- images ----

/// (H, W, 3) float32 copy of an image: the values the EXR writer stores, bit for bit.
py::array_t<float> toArray(const Image& img) {
    py::array_t<float> a({static_cast<py::ssize_t>(img.height), static_cast<py::ssize_t>(img.width), static_cast<py::ssize_t>(3)});
    float* out = a.mutable_data();
    for (std::size_t i = 0; i < img.pixels.size(); ++i)
        for (int c = 0; c < 3; ++c) out[3 * i + c] = static_cast<float>(img.pixels[i][c]);
    return a;
}

Image fromArray(const py::array& input) {
    const auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(input);
    if (!a) throw InputError("image: expected a numeric array of shape (H, W, 3) or (H, W)");
    const bool grey = a.ndim() == 2;
    if (!(grey || (a.ndim() == 3 && a.shape(2) == 3)))
        throw InputError(fmt::format("image: shape must be (H, W, 3) or (H, W), got {}", py::str(input.attr("shape")).cast<std::string>()));
    const long h = static_cast<long>(a.shape(0)), w = static_cast<long>(a.shape(1));
    if (w < 1 || h < 1) throw InputError(fmt::format("image: {}x{} has no pixels", w, h));
    if (w * h > kMaxImagePixels) throw InputError(fmt::format("image: {}x{} is too large (at most {} pixels)", w, h, kMaxImagePixels));
    Image img(static_cast<int>(w), static_cast<int>(h));
    const double* in = a.data();
    for (std::size_t i = 0; i < img.pixels.size(); ++i)
        for (int c = 0; c < 3; ++c) {
            const double v = in[grey ? i : 3 * i + c];
            if (!std::isfinite(v))
                throw InputError(fmt::format("image: pixel (x {}, y {}) has the non-finite value {}", i % img.width, i / img.width, v));
            img.pixels[i][c] = v;
        }
    return img;
}

// ---- render ----

/// A Scene argument: a Scene, or a spec string loaded on the spot (its errors raised as load_scene's).
std::shared_ptr<PyScene> sceneArgument(const py::object& scene) {
    if (py::isinstance<PyScene>(scene)) return scene.cast<std::shared_ptr<PyScene>>();
    if (py::isinstance<py::str>(scene)) return loadPyScene(scene.cast<std::string>());
    throw py::type_error(fmt::format("scene: expected a symphong.Scene or a spec string, got {}",
                                     py::str(py::type::of(scene).attr("__name__")).cast<std::string>()));
}

py::tuple renderPy(const py::object& sceneArg, const std::string& estimatorName, const std::string& sampler, long long spp, long long width,
                   long long height, long long maxDepth, const py::int_& seed, long long threads, bool nee, int symmetricN,
                   const std::string& symmetricMode, bool paperRefined, bool variance, const std::optional<bool>& progress, int symmetricOrbit,
                   long long split, long long firstBounceStream, bool jointFirstBounce) {
    RenderSettings s;
    s.spp = checkedRange<std::uint32_t>("spp", spp, 1, 1000000);
    s.width = checkedRange<int>("width", width, 1, 16384);
    s.height = checkedRange<int>("height", height, 1, 16384);
    if (static_cast<long>(s.width) * s.height > kMaxImagePixels)
        throw InputError(fmt::format("image size {}x{} is too large (at most {} pixels)", s.width, s.height, kMaxImagePixels));
    requireImageMemory(s.width, s.height);
    s.trace.maxDepth = checkedRange<int>("max_depth", maxDepth, 0, 1024);
    s.seed = checkedSeed(seed);
    s.threads = checkedRange<int>("threads", threads, 0, 4096);
    s.trace.nextEvent = nee;
    s.trace.firstHitSplit = checkedRange<int>("split", split, 1, 64);
    s.trace.firstBounceStream = checkedRange<std::uint32_t>("first_bounce_stream", firstBounceStream, 0, 1000000);
    s.trace.jointFirstBounce = jointFirstBounce;
    const auto& samplers = samplerNames();
    if (std::find(samplers.begin(), samplers.end(), sampler) == samplers.end())
        throw InputError(fmt::format("sampler: unknown sampler '{}' (valid: {})", sampler, fmt::join(samplers, ", ")));
    s.sampler = sampler;
    std::unique_ptr<Estimator> estimator;
    try {
        estimator = makeEstimator(estimatorName, estimatorOptions(symmetricN, paperRefined, symmetricMode, symmetricOrbit));
    } catch (const std::invalid_argument& e) {
        throw InputError(fmt::format("estimator: {}", e.what()));
    }
    const std::shared_ptr<PyScene> scene = sceneArgument(sceneArg);
    const bool showProgress = progress.value_or(stderrIsTerminal());

    const RenderResult r = runInterruptible([&](const std::atomic<bool>& cancel) {
        RenderSettings settings = s;
        settings.cancel = &cancel;
        std::atomic<std::uint64_t> done{0};
        ProgressBar bar(done, static_cast<std::uint64_t>(s.width) * s.height * s.spp, "samples", showProgress);
        RenderResult result = render(scene->scene(), scene->accel(), *estimator, settings, &done);
        bar.finish();
        return result;
    });
    const double secs = std::max(r.stats.seconds, 1e-9);
    py::dict stats;
    stats["seconds"] = r.stats.seconds;
    stats["rays"] = r.stats.rays;
    stats["samples"] = r.stats.samples;
    stats["bad_samples"] = r.stats.badSamples;
    stats["mrays_per_second"] = r.stats.rays / secs / 1e6;
    stats["samples_per_second"] = r.stats.samples / secs;
    stats["estimator"] = estimator->name();
    stats["sampler"] = r.sampler;
    stats["spp"] = s.spp;
    stats["width"] = s.width;
    stats["height"] = s.height;
    stats["seed"] = s.seed;
    if (variance) return py::make_tuple(toArray(r.image), stats, toArray(r.variance));
    return py::make_tuple(toArray(r.image), stats);
}

// ---- furnace and study ----

py::object jsonLoads(const std::string& text) { return py::module_::import("json").attr("loads")(text); }

py::object furnacePy(const py::object& estimators, const py::object& environments, double rhoD, double rhoS, const py::object& n,
                     const py::object& theta, double phi, long long repeats, const py::int_& seed, const std::string& sampler,
                     long long directions, bool grid, int symmetricN, const std::string& symmetricMode, bool paperRefined,
                     double diskTheta, double diskPhi, double diskRadius, double band) {
    FurnaceTable t;
    t.estimators = nameList(estimators, estimatorNames());
    t.environments = nameList(environments, environmentNames());
    t.exponents = grid ? furnaceGridExponents() : numberList<double>(n);
    t.thetas = grid ? furnaceGridThetas() : numberList<double>(theta);
    t.rhoD = rhoD, t.rhoS = rhoS, t.phiDeg = phi;
    t.repeats = checkedRange<int>("repeats", repeats, 2, 100000000);
    t.seed = checkedSeed(seed);
    t.sampler = sampler;
    t.directions = checkedRange<int>("directions", directions, 1, 1000000);
    t.options = estimatorOptions(symmetricN, paperRefined, symmetricMode);
    t.environment.diskTheta = diskTheta, t.environment.diskPhi = diskPhi;
    t.environment.diskRadius = diskRadius, t.environment.bandDegrees = band;
    const auto rows = runInterruptible([&](const std::atomic<bool>& cancel) { return runFurnaceTable(t, {}, &cancel); });
    return jsonLoads(furnaceJson(rows));
}

py::tuple studyPy(const py::object& scene, const py::object& estimators, const py::object& samplers, const py::object& modes,
                  const py::object& spp, long long repeats, long long width, long long height, long long maxDepth, const py::int_& seed,
                  long long threads, const std::optional<std::string>& reference, long long referenceSpp, const std::string& referenceEstimator,
                  const std::string& referenceSampler, const std::string& out, long long heatmapSpp, int symmetricN, bool paperRefined,
                  bool plots, const std::optional<std::string>& python, const std::optional<bool>& progress) {
    StudyConfig c;
    if (py::isinstance<PyScene>(scene))
        c.scene = scene.cast<const PyScene&>().spec();
    else if (py::isinstance<py::str>(scene))
        c.scene = scene.cast<std::string>();
    else
        throw py::type_error("scene: expected a symphong.Scene or a spec string");
    c.estimators = nameList(estimators, estimatorNames());
    c.samplers = nameList(samplers, samplerNames());
    c.modes.clear();
    for (const std::string& m : nameList(modes, {"branch", "spread"})) {
        try {
            c.modes.push_back(parseSymmetricMode(m));
        } catch (const std::invalid_argument& e) {
            throw InputError(fmt::format("symmetric_modes: {}", e.what()));
        }
    }
    c.spps.clear();
    for (long long v : numberList<long long>(spp)) c.spps.push_back(checkedRange<std::uint32_t>("spp", v, 1, 1000000));
    c.repeats = checkedRange<int>("repeats", repeats, 1, 1000);
    c.width = checkedRange<int>("width", width, 1, 4096);
    c.height = checkedRange<int>("height", height, 1, 4096);
    c.maxDepth = checkedRange<int>("max_depth", maxDepth, 0, 1024);
    c.seed = checkedSeed(seed);
    c.threads = checkedRange<int>("threads", threads, 0, 4096);
    c.referencePath = reference.value_or("");
    c.referenceSpp = checkedRange<std::uint32_t>("reference_spp", referenceSpp, 1, 10000000);
    c.referenceEstimator = referenceEstimator;
    const auto& allSamplers = samplerNames();
    if (std::find(allSamplers.begin(), allSamplers.end(), referenceSampler) == allSamplers.end())
        throw InputError(fmt::format("reference_sampler: unknown sampler '{}' (valid: {})", referenceSampler, fmt::join(allSamplers, ", ")));
    c.referenceSampler = referenceSampler;
    c.outDir = out;
    c.heatmapSpp = checkedRange<std::uint32_t>("heatmap_spp", heatmapSpp, 0, 1000000);
    c.options = estimatorOptions(symmetricN, paperRefined, "branch");
    c.plots = plots;
    c.python = python.value_or("");
    const bool showProgress = progress.value_or(stderrIsTerminal());
    const StudyOutcome outcome =
        runInterruptible([&](const std::atomic<bool>& cancel) { return runStudy(c, &cancel, showProgress); });
    if (c.plots && !outcome.plotted) throw std::runtime_error("the study's plots could not be made (needs python3 with matplotlib); pass plots=False to skip them");
    const std::filesystem::path dir(c.outDir);
    py::object results = jsonLoads(readTextFile((dir / "results.json").string()));
    return py::make_tuple(results["rows"], (dir / "report.md").string());
}

// ---- docstrings ----

const char* const kModuleDoc = R"(symphong: a Phong path tracer built to compare Monte Carlo estimators, symmetric sampling among them.

    scene = symphong.load_scene('cornell')            # or an .obj / .json file
    image, stats = symphong.render(scene, spp=16)     # float32 (H, W, 3) linear radiance
    symphong.write_image('cornell.png', image)

render, furnace and study take the command line's options as keyword arguments with the same defaults
(--max-depth is max_depth, and so on) and give the same numbers: render's image is bit for bit the EXR
that `symphong render` writes with the same settings, at any thread count. Bad input raises ValueError
(FileNotFoundError for a missing file) with the command line's message. Renders, furnaces and studies run
with the GIL released; Ctrl-C raises KeyboardInterrupt within a tile's time. Guide: docs/python.md.)";

std::string renderDoc() {
    return "render(scene, estimator='phong', sampler='" + std::string(kDefaultSampler) +
           "', spp=64, width=512, height=512, max_depth=16, seed=1, threads=0, nee=True, "
           "symmetric_n=1, symmetric_mode='branch', paper_refined=False, variance=False, progress=None, symmetric_orbit=2, split=1, "
           "first_bounce_stream=0)\n\n"
           "Renders `scene` (a Scene, or a spec string for load_scene) with the path tracer.\n\n"
           "Returns (image, stats), or (image, stats, variance) with variance=True:\n"
           "  image     float32 array (height, width, 3): linear radiance, row 0 at the top; bit for bit the EXR\n"
           "            that `symphong render` writes with the same settings.\n"
           "  stats     dict: seconds, rays, samples, bad_samples, mrays_per_second, samples_per_second,\n"
           "            estimator, sampler (the one used: an estimator may require its own), spp, width, height, seed.\n"
           "  variance  float32 array (height, width, 3): per-pixel variance of the mean (sample variance / spp).\n\n"
           "threads=0 uses every core; the image does not depend on it. nee=False turns light sampling off\n"
           "(--no-nee). symmetric_n, symmetric_mode ('branch' or 'spread'), symmetric_orbit and paper_refined set the set\n"
           "estimators. split=K traces K directions from each camera sample's first hit (--split). first_bounce_stream\n"
           "gives the first-bounce directions other random numbers, every other decision keeping its own (the\n"
           "variance budget, --first-bounce-stream).\n"
           "progress: draw a progress bar on stderr (default: when stderr is a terminal).\n"
           "The GIL is released while rendering; Ctrl-C raises KeyboardInterrupt after the tiles in flight.\n\n"
           "Estimators:\n" +
           estimatorHelp() + "\n\nSamplers:\n" + samplerHelp() + "\n";
}

const char* const kFurnaceDoc = R"(furnace(estimators='all', environments='constant', rho_d=0.3, rho_s=0.6, n=10, theta=30, phi=0, repeats=10000, seed=1, sampler=..., directions=16, grid=False, symmetric_n=1, symmetric_mode='branch', paper_refined=False, disk_theta=30, disk_phi=180, disk_radius=10, band=15)

The single-point furnace of `symphong furnace`: each estimator evaluated `repeats` times at one shading
point (grey Phong material rho_d, rho_s, exponent n, view angle theta from the normal, azimuth phi) under an
environment whose reflected radiance is known exactly.

estimators, environments: 'all', 'a,b' or a list of names (environments: constant, gradient, disk, band,
halfspace). n, theta: a number or a list; grid=True runs n in {1,10,100,1000,10000} x theta in {0,30,60,85}.
Returns a list of dicts, one per environment x n x theta x estimator, in that order, with the keys and
values of `symphong furnace --json` (estimate, std_error, exact, relative_bias, z, variance,
directions_per_estimate, variance_times_directions, seconds_per_estimate, efficiency, ...). The same
arguments give the same rows as the command line, timings aside.)";

const char* const kStudyDoc = R"(study(scene='cornell', estimators='cosine,stratified,phong,symmetric,symmetric-shifted,paper', samplers=..., symmetric_modes='branch', spp=(1, 4, 16, 64), repeats=4, width=128, height=128, max_depth=16, seed=1, threads=0, reference=None, reference_spp=2048, reference_estimator='phong', reference_sampler='independent', out='out/study', heatmap_spp=0, symmetric_n=1, paper_refined=False, plots=True, python=None, progress=None)

Runs `symphong study`: renders `scene` (a Scene or a spec string) with each estimator under each sampler
(the set estimators in each of symmetric_modes), at each spp, `repeats` independent times, against a
reference (rendered at reference_spp and cached in `out`, or the EXR file `reference`), and writes
results.csv, results.json, plots, heat maps, crops and report.md into `out`.

Returns (rows, report_path): rows is the list of dicts of results.json's "rows" (one per estimator x spp x
repeat). Lists may be given as 'a,b' strings or Python lists. Ctrl-C raises KeyboardInterrupt and keeps the
finished rows in out/results.csv. plots=False skips matplotlib; python names the interpreter for the plots.)";

}  // namespace
}  // namespace symphong

PYBIND11_MODULE(symphong, m) {
    using namespace symphong;
    m.doc() = kModuleDoc;
    m.attr("__version__") = "0.1.0";

    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const MissingFileError& e) {
            PyErr_SetString(PyExc_FileNotFoundError, e.what());
        } catch (const InputError& e) {
            PyErr_SetString(PyExc_ValueError, e.what());
        }
    });

    py::class_<PyScene, std::shared_ptr<PyScene>>(m, "Scene", R"(A loaded scene: triangles with Phong materials, emitters, a camera.

Scene(spec) is load_scene(spec). The acceleration structure is built on the first render and kept.)")
        .def(py::init(&loadPyScene), py::arg("spec"))
        .def_property_readonly("name", [](const PyScene& s) { return s.scene().name; }, "the scene's name (output files are named after it)")
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
        .def_property_readonly("environment", [](const PyScene& s) {
            const Color& e = s.scene().environment;
            return py::make_tuple(e.x, e.y, e.z);
        }, "RGB radiance arriving from directions that leave the scene")
        .def(
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
                const int w = checkedRange<int>("width", width, 1, 16384), h = checkedRange<int>("height", height, 1, 16384);
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
                            accel.intersect(origin, dir, 0.0, std::numeric_limits<double>::infinity(), hit) ? static_cast<std::int64_t>(hit.prim) : -1;
                    }
                return out;
            },
            py::arg("width"), py::arg("height"),
            "(H, W) int64: the triangle that the camera ray through each pixel's centre hits first (-1: none), as render()\n"
            "frames a width x height image. For masks of surfaces when comparing images region by region.")
        .def_property_readonly(
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
        .def_property_readonly("warnings", [](const PyScene& s) { return s.scene().warnings; }, "the loader's non-fatal notes")
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

    static const std::string renderDocText = renderDoc();
    m.def("render", &renderPy, renderDocText.c_str(), py::arg("scene"), py::kw_only(), py::arg("estimator") = "phong",
          py::arg("sampler") = std::string(kDefaultSampler), py::arg("spp") = 64, py::arg("width") = 512, py::arg("height") = 512,
          py::arg("max_depth") = 16, py::arg("seed") = py::int_(1), py::arg("threads") = 0, py::arg("nee") = true,
          py::arg("symmetric_n") = 1, py::arg("symmetric_mode") = "branch", py::arg("paper_refined") = false,
          py::arg("variance") = false, py::arg("progress") = py::none(), py::arg("symmetric_orbit") = 2, py::arg("split") = 1,
          py::arg("first_bounce_stream") = 0, py::arg("joint_first_bounce") = false);

    m.def("furnace", &furnacePy, kFurnaceDoc, py::kw_only(), py::arg("estimators") = "all", py::arg("environments") = "constant",
          py::arg("rho_d") = 0.3, py::arg("rho_s") = 0.6, py::arg("n") = 10.0, py::arg("theta") = 30.0, py::arg("phi") = 0.0,
          py::arg("repeats") = 10000, py::arg("seed") = py::int_(1), py::arg("sampler") = std::string(kDefaultSampler),
          py::arg("directions") = 16, py::arg("grid") = false, py::arg("symmetric_n") = 1, py::arg("symmetric_mode") = "branch",
          py::arg("paper_refined") = false, py::arg("disk_theta") = 30.0, py::arg("disk_phi") = 180.0, py::arg("disk_radius") = 10.0,
          py::arg("band") = 15.0);

    m.def("study", &studyPy, kStudyDoc, py::arg("scene") = "cornell", py::kw_only(),
          py::arg("estimators") = "cosine,stratified,phong,symmetric,symmetric-shifted,paper",
          py::arg("samplers") = std::string(kDefaultSampler), py::arg("symmetric_modes") = "branch",
          py::arg("spp") = std::vector<int>{1, 4, 16, 64}, py::arg("repeats") = 4, py::arg("width") = 128, py::arg("height") = 128,
          py::arg("max_depth") = 16, py::arg("seed") = py::int_(1), py::arg("threads") = 0, py::arg("reference") = py::none(),
          py::arg("reference_spp") = 2048, py::arg("reference_estimator") = "phong", py::arg("reference_sampler") = "independent",
          py::arg("out") = "out/study", py::arg("heatmap_spp") = 0, py::arg("symmetric_n") = 1, py::arg("paper_refined") = false,
          py::arg("plots") = true, py::arg("python") = py::none(), py::arg("progress") = py::none());

    m.def("estimators", [] { return estimatorNames(); }, "The estimator names, as render(estimator=...) and furnace take them.");
    m.def("samplers", [] { return samplerNames(); }, "The sampler names, as render(sampler=...) takes them.");
    m.def("environments", [] { return environmentNames(); }, "The furnace's environment names.");

    m.def(
        "write_image",
        [](const std::string& path, const py::array& image, double exposure, bool exrHalf) {
            if (!(exposure > 0) || !std::isfinite(exposure)) throw InputError(fmt::format("exposure = {} must be a positive number", exposure));
            imageFormatFor(path);  // the extension first: no work for a name that cannot be written
            const Image img = fromArray(image);
            py::gil_scoped_release release;
            checkWritable(path);
            writeImage(img, path, exposure, exrHalf);
        },
        R"(write_image(path, image, exposure=1.0, exr_half=False)

Writes a linear RGB array of shape (H, W, 3) (or (H, W), grey) as .png (8-bit sRGB after multiplying by
exposure and clamping to [0, 1]) or .exr (32-bit float; 16-bit half with exr_half=True), atomically: the
file is either the complete image or untouched. Non-finite values raise ValueError.)",
        py::arg("path"), py::arg("image"), py::kw_only(), py::arg("exposure") = 1.0, py::arg("exr_half") = false);

    m.def(
        "read_image",
        [](const std::string& path) {
            Image img;
            {
                py::gil_scoped_release release;
                img = readExr(path);
            }
            return toArray(img);
        },
        R"(read_image(path) -> float32 array (H, W, 3)

Reads a linear RGB OpenEXR file (half or float), e.g. a reference image written by `symphong render -o x.exr`.)",
        py::arg("path"));
}
