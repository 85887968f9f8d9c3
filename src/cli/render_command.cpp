// `symphong render`: options from renderSchema() (render/settings.h), the scene loaded and checked on
// every rank, the image shared among MPI ranks and written by rank 0, one summary line.
#include "accel/accel.h"
#include "cli/commands.h"
#include "cli/interrupts.h"
#include "cli/schema_cli.h"
#include "distrib/mpi_job.h"
#include "distrib/render.h"
#include "estimators/estimator.h"
#include "io/image.h"
#include "io/input_error.h"
#include "render/progress.h"
#include "render/renderer.h"
#include "scene/scene.h"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>

namespace symphong {

std::unique_ptr<Estimator> estimatorOrInputError(const std::string& name, const EstimatorOptions& options) {
    try {
        return makeEstimator(name, options);
    } catch (const std::invalid_argument& e) {
        throw InputError(fmt::format("--estimator: {}", e.what()));
    }
}

void checkVarianceOutput(const std::string& path) {
    if (imageFormatFor(path) != ImageFormat::Exr)
        throw InputError(fmt::format("--variance-output {}: the variance is written as OpenEXR (name it .exr)", path));
    checkWritable(path);
}

CLI::App* addRenderCommand(CLI::App& app, RenderOptions& o) {
    CLI::App* r = app.add_subcommand("render", "Render a scene to a PNG or OpenEXR image with the path tracer.");
    r->footer(
        "SCENE is 'cornell' (the built-in Cornell box), a Wavefront .obj file (its .mtl beside it), a .ply file, a .gltf,\n"
        ".glb, .fbx, .dae or .3ds file (read through Assimp, with its camera and lights), or a .json scene file.\n"
        "Texture maps (MTL map_Kd/Ks/Ns/d/Ke; glTF base colour, metallic-roughness, emissive, alpha mask) are read from\n"
        "PNG, JPEG, HDR or EXR; a missing texture file is a warning, a corrupt one an error. A JSON scene's\n"
        "\"environment\": {\"map\": \"sky.hdr\"} lights the scene with a lat-long HDR image (docs/scene-format.md).\n"
        "A mesh or texture that would need more than 3/4 of this machine's memory is refused before it is read.\n"
        "Assimp 5.2 (Debian 12) itself can crash or exhaust memory on some malformed Collada (.dae) and FBX files: it\n"
        "reads each file first in a child process with a memory limit, so such a file is an error (exit code 2) naming\n"
        "it, not a crash; the loaders were fuzzed (docs/reliability.md). PLY is read by symphong's own reader.\n"
        "PNG output is 8-bit sRGB: linear radiance is multiplied by --exposure, clamped to [0,1], then sRGB-encoded.\n"
        "EXR output is linear RGB, 32-bit float (16-bit half with --exr-half).\n"
        "The same --seed gives the same image, bit for bit, at any --threads, with every sampler.\n"
        "Under 'mpirun -np N' the N processes share the image (the same bytes) and rank 0 writes it (docs/cluster.md).\n\n"
        "Estimators:\n" +
        estimatorHelp() + "\n\nSamplers (every random decision of a render draws from the sampler):\n" + samplerHelp());
    addSchemaOptions(r, o, renderSchema());
    return r;
}

int runRender(const RenderOptions& given, const std::set<std::string>& givenKeys, const MpiJob& job) {
    // Every rank checks the input; a failure on any rank stops all of them, reported once by rank 0.
    std::string error;
    std::unique_ptr<Estimator> estimator;
    Scene scene;
    std::string output;
    RenderOptions o = given;
    try {
        checkRenderOptions(o);  // before the scene's load: a bad option fails at once
        estimator = estimatorOrInputError(o.estimator, o.estimatorOptions);
        scene = loadScene(o.scene);
        finishRenderOptions(o, scene, o.scene, givenKeys);  // the scene's own settings, under the command line's
        if (!scene.renderSettings.empty()) estimator = estimatorOrInputError(o.estimator, o.estimatorOptions);
        output = o.output.empty() ? fmt::format("out/{}.png", scene.name) : o.output;
        if (job.root()) checkWritable(output);
        if (job.root() && !o.varianceOutput.empty()) checkVarianceOutput(o.varianceOutput);
    } catch (const InputError& e) {
        if (!job.active()) throw;
        error = e.what();
    }
    error = job.firstError(error);
    if (!error.empty()) throw InputError(error);
    if (job.root())
        for (const std::string& w : scene.warnings) fmt::print(stderr, "symphong: warning: {}\n", w);
    if (o.progressive()) return renderInPasses(o, scene, *estimator, output, job);

    const RenderSettings settings = renderSettings(o);

    const Accel accel(scene);
    std::atomic<std::uint64_t> done{0};
    const std::uint64_t total = static_cast<std::uint64_t>(o.width) * o.height * o.spp;
    RenderResult result;
    DistributedStats distributed;
    {
        const LauncherStopGuard guard(job, LauncherStop::EndRender);
        ProgressBar bar(done, total, "samples", job.root() && stderrIsTerminal());
        result = renderDistributed(job, scene, accel, *estimator, settings, &done, &distributed);
        bar.finish();
    }
    if (!job.root()) return 0;
    if (result.stats.badSamples > 0)
        fmt::print(stderr, "symphong: warning: {} non-finite path contributions were discarded\n", result.stats.badSamples);
    writeImage(result.image, output, o.exposure, o.exrHalf);
    if (!o.varianceOutput.empty()) writeExr(result.variance, o.varianceOutput);
    const double secs = std::max(result.stats.seconds, 1e-9);
    fmt::print("{}: {}x{}, {} spp, estimator {}, sampler {}, splitting {}{}: {:.2f} s, {:.2f} Mrays/s, {}samples/s -> {}\n", scene.name,
               o.width, o.height, o.spp, estimator->name(), result.sampler, o.splitting,
               job.size() > 1 ? fmt::format(", {} ranks (tiles {}, gather {:.3f} s)", job.size(), fmt::join(distributed.tilesPerRank, "/"),
                                            distributed.gatherSeconds)
                              : "",
               result.stats.seconds, result.stats.rays / secs / 1e6, ProgressBar::formatCount(result.stats.samples / secs), output);
    return 0;
}

}  // namespace symphong
