// render(): keyword arguments through renderSchema() (render/settings.h), the same checks as the command
// line (checkRenderOptions), the render with the GIL released, the image and its statistics.
#include "estimators/estimator.h"
#include "io/input_error.h"
#include "python/common.h"
#include "python/schema_py.h"
#include "render/long_render.h"
#include "render/progress.h"
#include "render/renderer.h"
#include "render/settings.h"

#include <fmt/format.h>
#include <pybind11/stl.h>

namespace symphong {

bool takeProgress(py::dict& kwargs) {
    const py::object progress = takeKeyword(kwargs, "progress", py::none());
    return progress.is_none() ? stderrIsTerminal() : progress.cast<bool>();
}

namespace {

/// render() with a stop rule, a pass size or a checkpoint (render/long_render.h); adds spp_reached,
/// stop_reason, relative_error and checkpoint to `stats`.
RenderResult renderInPassesPy(const RenderOptions& o, const PyScene& scene, const Estimator& estimator, bool showProgress,
                              py::dict& stats) {
    if (o.resume && o.checkpoint.empty()) throw InputError("resume=True needs checkpoint=PATH (the file to resume from and to write)");
    stopRules(o);  // its input errors first
    const LongRender run = runInterruptible([&](const std::atomic<bool>& cancel) {
        std::atomic<std::uint64_t> done{0};
        ProgressBar bar(done, static_cast<std::uint64_t>(o.width) * o.height * o.spp, "samples", showProgress);
        LongRender result = renderLong(o, scene.scene(), scene.accel(), estimator, o.checkpoint, &cancel, &done, nullptr,
                                       [](const std::string& message) { fmt::print(stderr, "symphong: {}\n", message); });
        bar.finish();
        return result;
    });
    stats["spp_reached"] = run.state.samplesReached();
    stats["stop_reason"] = stopReasonName(run.why);
    stats["relative_error"] = run.error;
    if (!o.checkpoint.empty()) stats["checkpoint"] = o.checkpoint;
    return resultOf(run.state, effectiveSampler(estimator, o.sampler));
}

py::tuple renderPy(const py::object& sceneArg, const py::kwargs& given) {
    py::dict kwargs = py::dict(given);  // a copy: the module's own keywords are taken out of it
    const bool variance = takeKeyword(kwargs, "variance", py::bool_(false)).cast<bool>();
    const bool showProgress = takeProgress(kwargs);
    RenderOptions o;
    pyschema::applyKwargs(o, renderSchema(), kwargs, "render");
    const std::shared_ptr<PyScene> scene = sceneArgument(sceneArg);
    finishRenderOptions(o, scene->scene(), scene->spec(), pyschema::givenKeys(renderSchema(), kwargs));
    std::unique_ptr<Estimator> estimator;
    try {
        estimator = makeEstimator(o.estimator, o.estimatorOptions);
    } catch (const std::invalid_argument& e) {
        throw InputError(fmt::format("estimator: {}", e.what()));
    }
    const RenderSettings s = renderSettings(o);

    py::dict stats;
    RenderResult r;
    if (o.progressive()) {
        r = renderInPassesPy(o, *scene, *estimator, showProgress, stats);
    } else {
        r = runInterruptible([&](const std::atomic<bool>& cancel) {
            RenderSettings settings = s;
            settings.cancel = &cancel;
            std::atomic<std::uint64_t> done{0};
            ProgressBar bar(done, static_cast<std::uint64_t>(s.width) * s.height * s.spp, "samples", showProgress);
            RenderResult result = render(scene->scene(), scene->accel(), *estimator, settings, &done);
            bar.finish();
            return result;
        });
        stats["spp_reached"] = s.spp;
        stats["stop_reason"] = "spp";
    }
    const double secs = std::max(r.stats.seconds, 1e-9);
    stats["seconds"] = r.stats.seconds;
    stats["cpu_seconds"] = r.stats.cpuSeconds;
    stats["rays"] = r.stats.rays;
    stats["samples"] = r.stats.samples;
    stats["paths"] = r.stats.paths;
    stats["bad_samples"] = r.stats.badSamples;
    stats["mrays_per_second"] = r.stats.rays / secs / 1e6;
    stats["samples_per_second"] = r.stats.samples / secs;
    stats["estimator"] = estimator->name();
    stats["sampler"] = r.sampler;
    stats["splitting"] = o.splitting;  // the one used: auto resolved
    stats["spp"] = s.spp;
    stats["width"] = s.width;
    stats["height"] = s.height;
    stats["seed"] = s.seed;
    if (variance) return py::make_tuple(toArray(r.image), stats, toArray(r.variance));
    return py::make_tuple(toArray(r.image), stats);
}

std::string renderDoc() {
    return "render(scene, " + pyschema::signature(renderSchema()) +
           ", variance=False, progress=None)\n\n"
           "Renders `scene` (a Scene, or a spec string for load_scene) with the path tracer.\n\n"
           "Returns (image, stats), or (image, stats, variance) with variance=True:\n"
           "  image     float32 array (height, width, 3): linear radiance, row 0 at the top; bit for bit the EXR\n"
           "            that `symphong render` writes with the same settings.\n"
           "  stats     dict: seconds, cpu_seconds (of every thread), rays, samples, paths (started: a split's or\n"
           "            a set's further directions count), bad_samples, mrays_per_second, samples_per_second, estimator, sampler (the one used: an estimator may require its own), spp, width, height, seed,\n"
           "            spp_reached and stop_reason ('spp', 'time limit', 'target error', 'interrupted'); in passes (time,\n"
           "            target_error, pass_spp, checkpoint or resume given) also relative_error (of the image mean) and checkpoint.\n"
           "  variance  float32 array (height, width, 3): per-pixel variance of the mean (sample variance / spp).\n\n"
           "progress: draw a progress bar on stderr (default: when stderr is a terminal).\n"
           "The GIL is released while rendering; Ctrl-C raises KeyboardInterrupt after the tiles in flight (with\n"
           "checkpoint=PATH, after writing the checkpoint: resume=True continues from it, bit for bit).\n\n"
           "Keyword arguments (those of `symphong render`, with the same defaults and checks; threads=0 uses every\n"
           "core, and the image does not depend on it):\n" +
           pyschema::keywordHelp(renderSchema()) + "\nEstimators:\n" + estimatorHelp() + "\n\nSamplers:\n" + samplerHelp() + "\n";
}

}  // namespace

void registerRender(py::module_& m) {
    static const std::string doc = renderDoc();
    m.def("render", &renderPy, doc.c_str(), py::arg("scene"));
    m.def(
        "estimators", [] { return estimatorNames(); }, "The estimator names, as render(estimator=...) and furnace take them.");
    m.def(
        "samplers", [] { return samplerNames(); }, "The sampler names, as render(sampler=...) takes them.");
}

}  // namespace symphong
