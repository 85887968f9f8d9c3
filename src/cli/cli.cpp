#include "cli/cli.h"

#include "accel/accel.h"
#include "estimators/estimator.h"
#include "io/image.h"
#include "io/input_error.h"
#include "render/progress.h"
#include "render/renderer.h"
#include "scene/scene.h"

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <cmath>
#include <cstdio>

namespace symphong {

namespace {

constexpr int kBadInput = 2;
constexpr long kMaxPixels = 64L * 1024 * 1024;

struct RenderOptions {
    std::string scene = "cornell";
    std::string estimator = "phong";
    std::uint32_t spp = 64;
    int width = 512, height = 512;
    int maxDepth = 16;
    std::uint64_t seed = 1;
    int threads = 0;
    std::string output;
    double exposure = 1.0;
    bool exrHalf = false;
    bool noNee = false;
};

void addRenderCommand(CLI::App& app, RenderOptions& o) {
    CLI::App* r = app.add_subcommand("render", "Render a scene to a PNG or OpenEXR image with the path tracer.");
    r->footer(
        "SCENE is 'cornell' (the built-in Cornell box), a Wavefront .obj file (its .mtl beside it), or a .json scene file.\n"
        "PNG output is 8-bit sRGB: linear radiance is multiplied by --exposure, clamped to [0,1], then sRGB-encoded.\n"
        "EXR output is linear RGB, 32-bit float (16-bit half with --exr-half).\n"
        "The same --seed gives the same image, bit for bit, at any --threads.\n\nEstimators:\n" + estimatorHelp());
    r->add_option("scene", o.scene, "cornell, FILE.obj or FILE.json")->capture_default_str();
    r->add_option("--estimator,-e", o.estimator, "reflected-radiance estimator: " + fmt::format("{}", fmt::join(estimatorNames(), ", ")))
        ->capture_default_str();
    r->add_option("--spp,-s", o.spp, "camera samples per pixel")->check(CLI::Range(1u, 1000000u))->capture_default_str();
    r->add_option("--width,-W", o.width, "image width in pixels")->check(CLI::Range(1, 16384))->capture_default_str();
    r->add_option("--height,-H", o.height, "image height in pixels")->check(CLI::Range(1, 16384))->capture_default_str();
    r->add_option("--max-depth,-d", o.maxDepth, "most scattering events per path (0: emitters only)")
        ->check(CLI::Range(0, 1024))
        ->capture_default_str();
    r->add_option("--seed", o.seed, "random seed")->capture_default_str();
    r->add_option("--threads,-t", o.threads, "worker threads, 0 = all cores")->check(CLI::Range(0, 4096))->capture_default_str();
    r->add_option("--output,-o", o.output, "output image, .png or .exr (default: out/<scene-name>.png)");
    r->add_option("--exposure", o.exposure, "linear scale applied before PNG clamping")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    r->add_flag("--exr-half", o.exrHalf, "write EXR as 16-bit half instead of 32-bit float");
    r->add_flag("--no-nee", o.noNee, "no light sampling: emitters are found only by the estimator's directions");
}

int runRender(const RenderOptions& o) {
    if (static_cast<long>(o.width) * o.height > kMaxPixels)
        throw InputError(fmt::format("image size {}x{} is too large (at most {} pixels)", o.width, o.height, kMaxPixels));
    if (!std::isfinite(o.exposure)) throw InputError(fmt::format("--exposure {} is not finite", o.exposure));
    const auto estimator = [&] {
        try {
            return makeEstimator(o.estimator);
        } catch (const std::invalid_argument& e) {
            throw InputError(fmt::format("--estimator: {}", e.what()));
        }
    }();
    Scene scene = loadScene(o.scene);
    for (const std::string& w : scene.warnings) fmt::print(stderr, "symphong: warning: {}\n", w);
    const std::string output = o.output.empty() ? fmt::format("out/{}.png", scene.name) : o.output;
    checkWritable(output);

    RenderSettings settings;
    settings.width = o.width;
    settings.height = o.height;
    settings.spp = o.spp;
    settings.seed = o.seed;
    settings.threads = o.threads;
    settings.trace.maxDepth = o.maxDepth;
    settings.trace.nextEvent = !o.noNee;

    const Accel accel(scene);
    std::atomic<std::uint64_t> done{0};
    const std::uint64_t total = static_cast<std::uint64_t>(o.width) * o.height * o.spp;
    RenderResult result;
    {
        ProgressBar bar(done, total, "samples", stderrIsTerminal());
        result = render(scene, accel, *estimator, settings, &done);
        bar.finish();
    }
    if (result.stats.badSamples > 0)
        fmt::print(stderr, "symphong: warning: {} non-finite path contributions were discarded\n", result.stats.badSamples);
    writeImage(result.image, output, o.exposure, o.exrHalf);
    const double secs = std::max(result.stats.seconds, 1e-9);
    fmt::print("{}: {}x{}, {} spp, estimator {}: {:.2f} s, {:.2f} Mrays/s, {}samples/s -> {}\n", scene.name, o.width, o.height,
               o.spp, estimator->name(), result.stats.seconds, result.stats.rays / secs / 1e6,
               ProgressBar::formatCount(result.stats.samples / secs), output);
    return 0;
}

}  // namespace

int runCli(int argc, const char* const* argv) {
    CLI::App app{"symphong: a Phong path tracer built to compare Monte Carlo estimators, symmetric sampling among them."};
    app.require_subcommand(1);
    RenderOptions renderOptions;
    addRenderCommand(app, renderOptions);
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        fmt::print(stderr, "symphong: error: {}\nRun 'symphong --help' or 'symphong render --help' for usage.\n", e.what());
        return kBadInput;
    }
    try {
        if (app.got_subcommand("render")) return runRender(renderOptions);
    } catch (const InputError& e) {
        fmt::print(stderr, "symphong: error: {}\n", e.what());
        return kBadInput;
    } catch (const std::exception& e) {
        fmt::print(stderr, "symphong: internal error: {}\n", e.what());
        return 1;
    }
    return 0;
}

}  // namespace symphong
