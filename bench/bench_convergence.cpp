// Error per unit time of every sampler x estimator: renders each scene at a fixed sample count with
// each combination, measures the MSE (and relMSE) of luminance against a high-spp reference (phong,
// independent sampler, cached as EXR; its own noise, known from its per-pixel variance, is subtracted),
// the render time, and the efficiency 1/(MSE x time). All renders of a scene run in one process, one
// after the other, on the same threads. Not a test: the figures go to docs/performance.md.
#include "accel/accel.h"
#include "estimators/estimator.h"
#include "io/image.h"
#include "render/renderer.h"
#include "scene/scene.h"
#include "compare/metrics.h"

#include <fmt/format.h>
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <thread>

using namespace symphong;
namespace fs = std::filesystem;

namespace {

struct Reference {
    Image image;
    double noise = 0;  ///< mean over pixels of the luminance variance of the reference's mean
};

Reference reference(const Scene& scene, const Accel& accel, const std::string& spec, int size, std::uint32_t spp, int threads,
                    const fs::path& cache) {
    fs::create_directories(cache);
    const std::string stem = fmt::format("{}-{}px-{}spp", scene.name, size, spp);
    const fs::path exr = cache / (stem + ".exr"), meta = cache / (stem + ".json");
    if (fs::exists(exr) && fs::exists(meta)) {
        std::ifstream in(meta);
        const auto j = nlohmann::json::parse(in);
        if (j.value("scene", std::string()) == spec) return {readExr(exr.string()), j.at("noise").get<double>()};
    }
    fmt::print(stderr, "bench_convergence: rendering the reference of {} ({} spp), cached in {}\n", spec, spp, exr.string());
    const auto est = makeEstimator("phong");
    RenderSettings rs;
    rs.width = rs.height = size;
    rs.spp = spp;
    rs.seed = 0xFEFE;
    rs.sampler = "independent";  // independent samples: the per-pixel variance of the mean is an honest error bar
    rs.threads = threads;
    const RenderResult r = render(scene, accel, *est, rs);
    double noise = 0;
    for (const Color& v : r.variance.pixels) noise += luminanceVariance(v) / static_cast<double>(r.variance.pixels.size());
    writeExr(r.image, exr.string(), false);
    std::ofstream(meta) << nlohmann::json{{"scene", spec}, {"noise", noise}, {"seconds", r.stats.seconds}}.dump(2);
    return {r.image, noise};
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"symphong: MSE, time and efficiency of every sampler x estimator against a high-spp reference"};
    int threads = static_cast<int>(std::thread::hardware_concurrency());
    int size = 256, repeats = 2;
    std::uint32_t spp = 64, referenceSpp = 8192;
    std::vector<std::string> scenes = {"cornell"};
    std::vector<std::string> estimators = {"cosine", "phong"};
    std::vector<std::string> samplers = samplerNames();
    std::vector<std::string> modes = {"branch"};
    std::string cache = "build/bench-cache";
    app.add_option("--scenes", scenes, "scenes (cornell or a scene file)")->delimiter(',')->capture_default_str();
    app.add_option("--estimators", estimators, "estimators")->delimiter(',')->capture_default_str();
    app.add_option("--samplers", samplers, "samplers")->delimiter(',')->capture_default_str();
    app.add_option("--symmetric-modes", modes, "modes of the set estimators (branch, spread)")->delimiter(',')->capture_default_str();
    app.add_option("--size", size, "image width and height")->capture_default_str();
    app.add_option("--spp", spp, "samples per pixel")->capture_default_str();
    app.add_option("--repeats", repeats, "renders per combination (different seeds); MSE and time are their means")->capture_default_str();
    app.add_option("--reference-spp", referenceSpp, "samples per pixel of the reference")->capture_default_str();
    app.add_option("--cache", cache, "directory for the cached references")->capture_default_str();
    app.add_option("--threads", threads, "worker threads")->capture_default_str();
    CLI11_PARSE(app, argc, argv);

    fmt::print("{}x{}, {} spp, {} repeat(s), {} threads; reference: phong + independent at {} spp\n\n", size, size, spp, repeats, threads,
               referenceSpp);
    fmt::print("| scene | estimator | sampler | mode | time (s) | MSE | relMSE | efficiency 1/(MSE x s) | vs cosine + independent |\n");
    fmt::print("|---|---|---|---|---:|---:|---:|---:|---:|\n");
    for (const std::string& spec : scenes) {
        const Scene scene = loadScene(spec);
        const Accel accel(scene);
        const Reference ref = reference(scene, accel, spec, size, referenceSpp, threads, cache);
        double baseline = 0;
        for (const std::string& name : estimators)
            for (const std::string& mode : modes) {
                EstimatorOptions options;
                options.symmetricMode = parseSymmetricMode(mode);
                const auto est = makeEstimator(name, options);
                const bool setEstimator = hasSymmetricModes(name);
                if (!setEstimator && mode != modes.front()) continue;
                for (const std::string& samplerName : samplers) {
                    if (!est->requiredSampler().empty() && samplerName != samplers.front()) continue;
                    RenderSettings rs;
                    rs.width = rs.height = size;
                    rs.spp = spp;
                    rs.sampler = samplerName;
                    rs.threads = threads;
                    rs.seed = 1;
                    render(scene, accel, *est, rs);  // warm-up
                    double mse = 0, relMse = 0, seconds = 0;
                    std::string used;
                    for (int k = 0; k < repeats; ++k) {
                        rs.seed = 1000 + static_cast<std::uint64_t>(k);
                        const RenderResult r = render(scene, accel, *est, rs);
                        const ImageError e = imageError(r.image, ref.image);
                        mse += std::max(e.mse - ref.noise, 0.0) / repeats;
                        relMse += e.relMse / repeats;
                        seconds += r.stats.seconds / repeats;
                        used = r.sampler;
                    }
                    const double eff = 1.0 / (mse * seconds);
                    if (name == "cosine" && used == "independent") baseline = eff;
                    fmt::print("| {} | {} | {} | {} | {:.2f} | {:.4g} | {:.4g} | {:.4g} | {} |\n", scene.name, name, used,
                               setEstimator ? mode : "-", seconds, mse, relMse, eff,
                               baseline > 0 ? fmt::format("{:.2f}x", eff / baseline) : std::string("-"));
                    std::fflush(stdout);
                }
            }
    }
    return 0;
}
