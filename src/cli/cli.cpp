#include "cli/cli.h"

#include "accel/accel.h"
#include "distrib/mpi_job.h"
#include "distrib/render.h"
#include "distrib/study.h"
#include "estimators/estimator.h"
#include "io/files.h"
#include "io/image.h"
#include "io/input_error.h"
#include "render/progress.h"
#include "render/renderer.h"
#include "scene/scene.h"
#include "study/furnace.h"
#include "study/study.h"

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>

#include <unistd.h>

namespace symphong {

namespace {

constexpr int kBadInput = 2;

struct RenderOptions {
    std::string scene = "cornell";
    std::string estimator = "phong";
    std::string sampler = std::string(kDefaultSampler);
    std::uint32_t spp = 64;
    int width = 512, height = 512;
    int maxDepth = 16;
    std::uint64_t seed = 1;
    int threads = 0;
    std::string output;
    double exposure = 1.0;
    bool exrHalf = false;
    bool noNee = false;
    int split = 1;
    std::uint32_t firstBounceStream = 0;
    bool jointFirstBounce = false;
    EstimatorOptions estimatorOptions;
};

void addEstimatorOptions(CLI::App* cmd, EstimatorOptions& o, bool withMode = true) {
    cmd->add_option("--symmetric-n", o.symmetricN, "N': (u,v) points per piece for paper, symmetric, symmetric-shifted")
        ->check(CLI::Range(1, 4096))
        ->capture_default_str();
    cmd->add_flag("--paper-refined", o.paperRefined, "paper: use the conclusion's finer lobe normalisation instead of Eq. (6)'s");
    cmd->add_option("--symmetric-orbit", o.symmetricOrbit,
                    "symmetric-mix: symmetric copies of one point used together, traced from one camera sample (branch) or "
                    "spread over consecutive camera samples (spread): 1, 2, 4 or 8")
        ->check(CLI::IsMember({1, 2, 4, 8}))
        ->capture_default_str();
    if (!withMode) return;
    cmd->add_option_function<std::string>(
           "--symmetric-mode",
           [&o](const std::string& name) {
               try {
                   o.symmetricMode = parseSymmetricMode(name);
               } catch (const std::invalid_argument& e) {
                   throw CLI::ValidationError("--symmetric-mode", e.what());
               }
           },
           "paper, symmetric*: 'branch' (a camera sample traces the whole set from its first hit; symmetric-mix: its orbit "
           "of --symmetric-orbit copies) or 'spread' (the set is spread over a pixel's camera samples, one piece or copy "
           "each) [default: branch]")
        ->type_name("MODE");
}

/// --sampler NAME, checked against the sampler names.
CLI::Option* addSamplerOption(CLI::App* cmd, std::string& sampler) {
    return cmd->add_option("--sampler", sampler, "sample generator: " + fmt::format("{}", fmt::join(samplerNames(), ", ")))
        ->check(CLI::IsMember(samplerNames()))
        ->capture_default_str();
}

std::unique_ptr<Estimator> estimatorOrInputError(const std::string& name, const EstimatorOptions& options) {
    try {
        return makeEstimator(name, options);
    } catch (const std::invalid_argument& e) {
        throw InputError(fmt::format("--estimator: {}", e.what()));
    }
}

void addRenderCommand(CLI::App& app, RenderOptions& o) {
    CLI::App* r = app.add_subcommand("render", "Render a scene to a PNG or OpenEXR image with the path tracer.");
    r->footer(
        "SCENE is 'cornell' (the built-in Cornell box), a Wavefront .obj file (its .mtl beside it), a .gltf, .glb, .ply,\n"
        ".fbx, .dae or .3ds file (read through Assimp, with its camera and lights), or a .json scene file.\n"
        "Texture maps (MTL map_Kd/Ks/Ns/d/Ke; glTF base colour, metallic-roughness, emissive, alpha mask) are read from\n"
        "PNG, JPEG, HDR or EXR; a missing texture file is a warning, a corrupt one an error. A JSON scene's\n"
        "\"environment\": {\"map\": \"sky.hdr\"} lights the scene with a lat-long HDR image (docs/scene-format.md).\n"
        "A mesh or texture that would need more than 3/4 of this machine's memory is refused before it is read.\n"
        "Known limit: Assimp 5.2 (Debian 12) itself can crash or exhaust memory on some malformed Collada (.dae) and FBX\n"
        "files, which symphong cannot prevent from outside; the loaders were fuzzed (docs/reliability.md).\n"
        "PNG output is 8-bit sRGB: linear radiance is multiplied by --exposure, clamped to [0,1], then sRGB-encoded.\n"
        "EXR output is linear RGB, 32-bit float (16-bit half with --exr-half).\n"
        "The same --seed gives the same image, bit for bit, at any --threads, with every sampler.\n"
        "Under 'mpirun -np N' the N processes share the image (the same bytes) and rank 0 writes it (docs/cluster.md).\n\n"
        "Estimators:\n" +
        estimatorHelp() + "\n\nSamplers (every random decision of a render draws from the sampler):\n" + samplerHelp());
    r->add_option("scene", o.scene, "cornell, FILE.obj, FILE.gltf/.glb/.ply/.fbx/.dae/.3ds or FILE.json")->capture_default_str();
    r->add_option("--estimator,-e", o.estimator, "reflected-radiance estimator: " + fmt::format("{}", fmt::join(estimatorNames(), ", ")))
        ->capture_default_str();
    addSamplerOption(r, o.sampler);
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
    r->add_option("--split", o.split,
                  "first-hit splitting: trace K directions per camera sample from its first hit (K calls of the estimator on "
                  "sub-samples of the pixel's pattern, each weighted 1/K)")
        ->check(CLI::Range(1, 64))
        ->capture_default_str();
    r->add_option("--first-bounce-stream", o.firstBounceStream,
                  "give the first hit's estimator other random numbers (stream S), every other decision of the path keeping its "
                  "own: renders that differ only in S measure the first bounce's share of the variance (docs/estimators.md)")
        ->check(CLI::Range(0, 1000000))
        ->capture_default_str();
    r->add_flag("--joint-first-bounce", o.jointFirstBounce,
                "sobol: the pixel position and the first bounce's direction from one 4D Owen-scrambled Sobol' pattern instead of "
                "two independently matched pairs (off by default: it lowers MSE for cosine but not for every estimator, "
                "docs/sampling.md)");
    r->add_flag("--no-nee", o.noNee, "no light sampling of emissive triangles: they are found only by the estimator's directions (point, spot and "
                "directional lights are still sampled: nothing else can reach them)");
    addEstimatorOptions(r, o.estimatorOptions);
}

// Interruptions. Ctrl-C stops a study cleanly (SIGINT): rows finished so far are kept. Under mpirun,
// Ctrl-C reaches the ranks as SIGTERM (mpirun turns its SIGINT into SIGTERM to every rank, then SIGKILL
// a second later), and so does the end of a job one of whose ranks died. Rank 0 then says so at once:
// a render ends (its image is only written after the last tile), a study stops as after Ctrl-C; the
// other ranks ignore the signal and follow rank 0 (or are killed by mpirun).
std::atomic<bool> gInterrupted{false};
std::atomic<bool> gRendering{false};
constexpr char kLauncherStopped[] = "symphong: the MPI launcher is stopping the job (Ctrl-C, or a rank ended)\n";

extern "C" void onInterrupt(int) { gInterrupted.store(true); }

extern "C" void onLauncherStopStudy(int) {
    if (!gInterrupted.exchange(true)) [[maybe_unused]] const auto n = ::write(STDERR_FILENO, kLauncherStopped, sizeof kLauncherStopped - 1);
}

extern "C" void onLauncherStopRender(int) {
    if (!gRendering.load()) return;  // writing the image: let it finish
    constexpr char tail[] = "symphong: no image was written\n";
    [[maybe_unused]] const auto a = ::write(STDERR_FILENO, kLauncherStopped, sizeof kLauncherStopped - 1);
    [[maybe_unused]] const auto b = ::write(STDERR_FILENO, tail, sizeof tail - 1);
    ::_exit(143);
}

enum class LauncherStop { EndRender, StopStudy };

/// Installs the interruption handlers for the scope of a render or a study, and restores the previous
/// ones. Without MPI: a study handles SIGINT and SIGTERM (a batch system's stop) alike; a render keeps
/// the default (the image is written atomically at the end, so nothing is left behind).
class LauncherStopGuard {
public:
    LauncherStopGuard(const MpiJob& job, LauncherStop what) {
        const bool shared = job.size() > 1;
        gInterrupted = false;
        if (what == LauncherStop::EndRender) {
            if (!shared || !job.root()) return;
            gRendering = true;
            install(SIGTERM, onLauncherStopRender);
        } else if (!job.root()) {
            install(SIGINT, SIG_IGN), install(SIGTERM, SIG_IGN);
        } else {
            install(SIGINT, onInterrupt), install(SIGTERM, shared ? onLauncherStopStudy : onInterrupt);
        }
    }
    ~LauncherStopGuard() {
        gRendering = false;
        for (const auto& [signal, handler] : previous_) std::signal(signal, handler);
    }
    LauncherStopGuard(const LauncherStopGuard&) = delete;
    LauncherStopGuard& operator=(const LauncherStopGuard&) = delete;

private:
    void install(int signal, void (*handler)(int)) { previous_.emplace_back(signal, std::signal(signal, handler)); }
    std::vector<std::pair<int, void (*)(int)>> previous_;
};

int runRender(const RenderOptions& o, const MpiJob& job) {
    // Every rank checks the input; a failure on any rank stops all of them, reported once by rank 0.
    std::string error;
    std::unique_ptr<Estimator> estimator;
    Scene scene;
    std::string output;
    try {
        if (static_cast<long>(o.width) * o.height > kMaxImagePixels)
            throw InputError(fmt::format("image size {}x{} is too large (at most {} pixels)", o.width, o.height, kMaxImagePixels));
        requireImageMemory(o.width, o.height);
        if (!std::isfinite(o.exposure)) throw InputError(fmt::format("--exposure {} is not finite", o.exposure));
        estimator = estimatorOrInputError(o.estimator, o.estimatorOptions);
        scene = loadScene(o.scene);
        output = o.output.empty() ? fmt::format("out/{}.png", scene.name) : o.output;
        if (job.root()) checkWritable(output);
    } catch (const InputError& e) {
        if (!job.active()) throw;
        error = e.what();
    }
    error = job.firstError(error);
    if (!error.empty()) throw InputError(error);
    if (job.root())
        for (const std::string& w : scene.warnings) fmt::print(stderr, "symphong: warning: {}\n", w);

    RenderSettings settings;
    settings.width = o.width;
    settings.height = o.height;
    settings.spp = o.spp;
    settings.seed = o.seed;
    settings.sampler = o.sampler;
    settings.threads = o.threads;
    settings.trace.maxDepth = o.maxDepth;
    settings.trace.nextEvent = !o.noNee;
    settings.trace.firstHitSplit = o.split;
    settings.trace.firstBounceStream = o.firstBounceStream;
    settings.trace.jointFirstBounce = o.jointFirstBounce;

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
    const double secs = std::max(result.stats.seconds, 1e-9);
    fmt::print("{}: {}x{}, {} spp, estimator {}, sampler {}{}: {:.2f} s, {:.2f} Mrays/s, {}samples/s -> {}\n", scene.name, o.width,
               o.height, o.spp, estimator->name(), result.sampler, job.size() > 1 ? fmt::format(", {} ranks (tiles {}, gather {:.3f} s)", job.size(), fmt::join(distributed.tilesPerRank, "/"), distributed.gatherSeconds) : "",
               result.stats.seconds, result.stats.rays / secs / 1e6, ProgressBar::formatCount(result.stats.samples / secs), output);
    return 0;
}

void addInfoCommand(CLI::App& app, std::string& scene) {
    CLI::App* i = app.add_subcommand("info", "Print what a scene file holds, as symphong loads it, without rendering.");
    i->footer("Triangles and vertices, the bounding box, the camera (given, or the automatic one), every material with its\n"
              "Phong parameters (rho_d, rho_s, n, emission) and how many triangles use it, the lights (point, spot,\n"
              "directional; the default sky's sun when the scene brings no light), the environment (constant, default sky or\n"
              "an HDR map), the textures (size, channels, wrap modes, and which material uses each for what), and the\n"
              "loader's warnings (a missing texture file is one).");
    i->add_option("scene", scene, "cornell, FILE.obj, FILE.gltf/.glb/.ply/.fbx/.dae/.3ds or FILE.json")->capture_default_str();
}

std::string triple(const Vec3& v) { return fmt::format("({:.6g}, {:.6g}, {:.6g})", v.x, v.y, v.z); }

int runInfo(const std::string& spec) {
    const Scene s = loadScene(spec);
    for (const std::string& w : s.warnings) fmt::print(stderr, "symphong: warning: {}\n", w);
    Vec3 lo, hi;
    s.bounds(lo, hi);
    std::size_t emissive = 0;
    std::vector<std::size_t> uses(s.materials.size(), 0);
    for (const Triangle& t : s.triangles) {
        ++uses[t.material];
        emissive += s.materials[t.material].isEmissive();
    }
    fmt::print("scene       {} (from {})\n", s.name, spec);
    fmt::print("triangles   {} ({} emissive), {} vertices, {} shading normals\n", s.triangles.size(), emissive, s.positions.size(),
               s.normals.size());
    fmt::print("bounds      {} to {} (size {})\n", triple(lo), triple(hi), triple(hi - lo));
    fmt::print("camera      position {}, target {}, up {}, vertical fov {:.4g} degrees\n", triple(s.camera.position), triple(s.camera.target),
               triple(s.camera.up), s.camera.fovY);
    fmt::print("materials   {}\n", s.materials.size());
    for (std::size_t i = 0; i < s.materials.size(); ++i) {
        const PhongMaterial& m = s.materials[i];
        fmt::print("  {:<20} rho_d {}  rho_s {}  n {:.6g}  emission {}  ({} triangles)\n", "'" + m.name + "'", triple(m.rhoD), triple(m.rhoS),
                   m.exponent, triple(m.emission), uses[i]);
        const MaterialTextures& tx = m.textures;
        if (!tx.any()) continue;
        std::string maps;
        const auto add = [&](const char* what, const TextureRef& r) {
            if (r.present()) maps += fmt::format("{}{} = texture {}", maps.empty() ? "" : ", ", what, r.index);
        };
        const bool pbr = tx.model == MaterialTextures::Model::MetallicRoughness;
        add(pbr ? "base colour" : "rho_d", tx.diffuse);
        add("rho_s", tx.specular);
        add("n", tx.exponent);
        add("metallic-roughness", tx.metallicRoughness);
        add("emission", tx.emission);
        add("cut-out", tx.alpha);
        if (pbr) maps += fmt::format(" (glTF factors: base colour {}, metallic {:.4g}, roughness {:.4g})", triple(tx.baseColor), tx.metallic, tx.roughness);
        else if (tx.reflectance()) maps += " (times the constants above)";
        fmt::print("  {:<20} maps: {}\n", "", maps);
    }
    fmt::print("lights      {}\n", s.lights.size());
    for (const Light& l : s.lights) {
        switch (l.type) {
            case Light::Type::Point: fmt::print("  point       position {}, intensity {}\n", triple(l.position), triple(l.intensity)); break;
            case Light::Type::Spot:
                fmt::print("  spot        position {}, direction {}, intensity {}, cone {:.4g} to {:.4g} degrees\n", triple(l.position),
                           triple(l.direction), triple(l.intensity), std::acos(l.cosInner) * 180 / kPi, std::acos(l.cosOuter) * 180 / kPi);
                break;
            case Light::Type::Directional:
                fmt::print("  directional direction {}, irradiance {}\n", triple(l.direction), triple(l.intensity));
                break;
        }
    }
    if (s.environmentMap) {
        const EnvironmentMap& e = *s.environmentMap;
        fmt::print("environment HDR map {} ({} x {}), scale {:.6g}, rotation {:.4g} degrees, {} filtering; integral of Y(L) dw = {:.6g}\n",
                   e.image().name(), e.image().width(), e.image().height(), e.scale(), e.rotationDegrees(), filterName(e.filter()),
                   e.luminanceIntegral());
    } else if (s.sky) {
        fmt::print("environment default sky: zenith {}, horizon {}, ground {}\n", triple(s.sky->zenith), triple(s.sky->horizon), triple(s.sky->ground));
    } else {
        fmt::print("environment constant radiance {}\n", triple(s.environment));
    }
    std::uint64_t textureBytes = 0;
    for (const Texture& t : s.textures) textureBytes += t.bytes();
    fmt::print("textures    {} ({:.3g} MiB), {} texture coordinates\n", s.textures.size(), static_cast<double>(textureBytes) / (1024.0 * 1024.0), s.uvs.size());
    for (std::size_t i = 0; i < s.textures.size(); ++i) {
        const Texture& t = s.textures[i];
        fmt::print("  {:<3} {} x {}, {} channel{}, wrap {}/{}: {}\n", i, t.width(), t.height(), t.channels(), t.channels() > 1 ? "s" : "",
                   wrapModeName(t.wrapU), wrapModeName(t.wrapV), t.name());
    }
    fmt::print("warnings    {}\n", s.warnings.size());
    for (const std::string& w : s.warnings) fmt::print("  {}\n", w);
    return 0;
}

struct FurnaceOptions {
    FurnaceTable table;  ///< the options bind to its fields; lists and --grid fill the rest
    std::string estimators = "all";
    std::string environments = "constant";
    bool grid = false;
    std::string json;
};

void addFurnaceCommand(CLI::App& app, FurnaceOptions& o) {
    CLI::App* f = app.add_subcommand("furnace", "Measure reflected-radiance estimators at one shading point against exact values.");
    f->footer(
        "Evaluates each estimator M times at one shading point (grey Phong material, view angle THETA from the normal,\n"
        "azimuth PHI) under an incoming radiance whose reflected value is known exactly, and prints the mean, its\n"
        "standard error, the exact value, the relative bias and its z-score, the variance of one estimate, the\n"
        "variance per direction (var x directions: estimators compared at an equal number of directions), the\n"
        "time per estimate and the efficiency 1/(var x time). One estimate is one call of a set-returning estimator\n"
        "(paper, symmetric* in branch mode), the mean of one whole spread set (spread mode), or the mean of --directions\n"
        "calls of the others. Estimate r is pixel r of --sampler and call i its sample i, so a stratified or sobol sampler\n"
        "stratifies the calls of an estimate.\n"
        "Environments: constant (L = 1), gradient (quadratic sky), disk (small disk light), band (horizon band),\n"
        "halfspace. --grid runs n in {1,10,100,1000,10000} x theta in {0,30,60,85}.\n");
    f->add_option("--estimator,-e", o.estimators, "estimators, comma-separated, or all")->capture_default_str();
    f->add_option("--environment", o.environments, "environments, comma-separated, or all")->capture_default_str();
    f->add_option("--rho-d", o.table.rhoD, "diffuse albedo")->check(CLI::Range(0.0, 1.0))->capture_default_str();
    f->add_option("--rho-s", o.table.rhoS, "specular albedo")->check(CLI::Range(0.0, 1.0))->capture_default_str();
    f->add_option("--n", o.table.exponents, "Phong exponents")->delimiter(',')->check(CLI::Range(0.0, 1e6))->capture_default_str();
    f->add_option("--theta", o.table.thetas, "view angles from the normal, degrees")->delimiter(',')->check(CLI::Range(0.0, 89.9))->capture_default_str();
    f->add_option("--phi", o.table.phiDeg, "view azimuth, degrees")->check(CLI::Range(-360.0, 360.0))->capture_default_str();
    f->add_option("--repeats,-M", o.table.repeats, "independent estimates")->check(CLI::Range(2, 100000000))->capture_default_str();
    f->add_option("--seed", o.table.seed, "random seed")->capture_default_str();
    addSamplerOption(f, o.table.sampler);
    f->add_option("--directions", o.table.directions, "calls per estimate for one-direction estimators")->check(CLI::Range(1, 1000000))->capture_default_str();
    f->add_option("--disk-theta", o.table.environment.diskTheta, "disk light: polar angle, degrees")->check(CLI::Range(0.0, 180.0))->capture_default_str();
    f->add_option("--disk-phi", o.table.environment.diskPhi, "disk light: azimuth, degrees")->check(CLI::Range(-360.0, 360.0))->capture_default_str();
    f->add_option("--disk-radius", o.table.environment.diskRadius, "disk light: angular radius, degrees")->check(CLI::Range(0.01, 89.9))->capture_default_str();
    f->add_option("--band", o.table.environment.bandDegrees, "horizon band height, degrees")->check(CLI::Range(0.01, 90.0))->capture_default_str();
    f->add_flag("--grid", o.grid, "n in {1,10,100,1000,10000} x theta in {0,30,60,85}");
    f->add_option("--json", o.json, "also write the results as JSON to this file");
    addEstimatorOptions(f, o.table.options);
}

std::vector<std::string> splitList(const std::string& text, const std::vector<std::string>& all, const char* what) {
    if (text == "all") return all;
    std::vector<std::string> out;
    std::size_t start = 0;
    while (start <= text.size()) {
        const auto comma = text.find(',', start);
        std::string item = text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
        if (std::find(all.begin(), all.end(), item) == all.end())
            throw InputError(fmt::format("{}: unknown name '{}' (valid: {}, or all)", what, item, fmt::join(all, ", ")));
        out.push_back(item);
        if (comma == std::string::npos) break;
        start = comma + 1;
    }
    return out;
}

int runFurnaceCommand(const FurnaceOptions& o) {
    FurnaceTable table = o.table;
    table.estimators = splitList(o.estimators, estimatorNames(), "--estimator");
    table.environments = splitList(o.environments, environmentNames(), "--environment");
    for (const auto& e : table.estimators) estimatorOrInputError(e, table.options);
    if (!o.json.empty()) {
        try {
            checkCanCreate(o.json);  // fails now, not after the run, if it cannot be written
        } catch (const InputError& e) {
            throw InputError(fmt::format("--json {}", e.what()));
        }
    }
    if (o.grid) table.exponents = furnaceGridExponents(), table.thetas = furnaceGridThetas();
    fmt::print("rho_d {}  rho_s {}  repeats {}  seed {}  sampler {}  (one-direction estimators: {} calls per estimate)\n", table.rhoD,
               table.rhoS, table.repeats, table.seed, table.sampler, table.directions);
    fmt::print("{:<18} {:<10} {:>6} {:>5} {:>6} {:>11} {:>10} {:>11} {:>9} {:>8} {:>10} {:>10} {:>9} {:>10}\n", "estimator",
               "environmt", "n", "theta", "dirs", "estimate", "std.err", "exact", "rel.bias", "z", "var(1 est)", "var x dirs",
               "us/est", "efficiency");
    const auto rows = runFurnaceTable(table, [](const FurnaceResult& r) {
        fmt::print("{:<18} {:<10} {:>6} {:>5} {:>6.1f} {:>11.6f} {:>10.2e} {:>11.6f} {:>+8.2f}% {:>8.2f} {:>10.3e} {:>10.3e} {:>9.3f} {:>10.3e}\n",
                   r.estimator, r.environment, r.n, r.thetaDeg, r.directionsPerEstimate, r.estimate, r.stdError, r.exact,
                   100 * r.relativeBias, r.z, r.variance, r.varianceTimesDirections, 1e6 * r.secondsPerEstimate, r.efficiency);
    });
    if (!o.json.empty()) writeFile(o.json, furnaceJson(rows));
    return 0;
}

struct StudyOptions {
    StudyConfig config;
    std::string estimators = "cosine,stratified,phong,symmetric,symmetric-shifted,paper";
    std::string samplers = std::string(kDefaultSampler);
    std::string modes = "branch";
    std::vector<std::uint32_t> spps = {1, 4, 16, 64};
    std::string splitEstimators = "phong,symmetric-mix";
    bool noPlots = false;
};

void addStudyCommand(CLI::App& app, StudyOptions& o) {
    CLI::App* s = app.add_subcommand("study", "Compare estimators on a scene: bias, RMSE, variance, time, efficiency, with plots and a report.");
    s->footer(
        "Renders SCENE with each estimator (under each of --samplers, and the set estimators in each of --symmetric-modes)\n"
        "at each sample count, --repeats independent times, against a reference image\n"
        "(rendered once at --reference-spp with --reference-estimator and cached in DIR, or given with --reference), and\n"
        "writes into DIR: results.csv and results.json (one row per estimator x spp x repeat), convergence plots against\n"
        "samples and time with the 1/sqrt(N) slope, an efficiency bar chart (PNG and SVG), per-pixel error heat maps,\n"
        "crops of the renders, and report.md with a conclusion computed from the numbers. Ctrl-C stops cleanly and keeps\n"
        "the finished rows. With no arguments: the built-in Cornell box, 128x128, a few minutes on 2 cores.\n"
        "Under 'mpirun -np N' the N processes share each render; rank 0 writes the same rows (times aside) and the report\n"
        "(docs/cluster.md).\n");
    s->add_option("scene", o.config.scene, "cornell, FILE.obj or FILE.json")->capture_default_str();
    s->add_option("--estimators,-e", o.estimators, "estimators, comma-separated, or all")->capture_default_str();
    s->add_option("--samplers", o.samplers, "samplers, comma-separated, or all: every estimator runs under each")->capture_default_str();
    s->add_option("--symmetric-modes", o.modes, "modes of paper and symmetric*, comma-separated: branch, spread, or all")->capture_default_str();
    s->add_option("--spp", o.spps, "samples per pixel, comma-separated")->delimiter(',')->check(CLI::Range(1u, 1000000u))->capture_default_str();
    s->add_option("--splits", o.config.splits,
                  "first-hit splitting: for each K > 1 also run every estimator of --split-estimators with K directions per "
                  "camera sample from its first hit (a variant '+splitK'), comma-separated")
        ->delimiter(',')
        ->check(CLI::Range(1, 64));
    s->add_option("--split-estimators", o.splitEstimators, "the estimators that --splits applies to, comma-separated")->capture_default_str();
    s->add_option("--budget-pairs", o.config.budgetPairs,
                  "variance budget: pairs of renders per variant at the top spp that differ only in the first bounce's random "
                  "numbers; the report gives the first bounce's share of the pixel variance (0: none)")
        ->check(CLI::Range(0, 64))
        ->capture_default_str();
    s->add_flag("--joint-first-bounce", o.config.jointFirstBounce,
                "every render with the pixel position and the first bounce from one 4D Sobol' pattern (render --joint-first-bounce)");
    s->add_option("--repeats,-R", o.config.repeats, "independent renders per estimator and spp")->check(CLI::Range(1, 1000))->capture_default_str();
    s->add_option("--reference", o.config.referencePath, "reference image (linear EXR of the same size) instead of rendering one");
    s->add_option("--reference-spp", o.config.referenceSpp, "samples per pixel of the rendered reference")
        ->check(CLI::Range(1u, 10000000u))
        ->capture_default_str();
    s->add_option("--reference-estimator", o.config.referenceEstimator, "unbiased estimator for the reference")->capture_default_str();
    s->add_option("--reference-sampler", o.config.referenceSampler, "sampler of the reference (independent: its own noise is known)")
        ->check(CLI::IsMember(samplerNames()))
        ->capture_default_str();
    s->add_option("--out,-o", o.config.outDir, "output directory")->capture_default_str();
    s->add_option("--width,-W", o.config.width, "image width")->check(CLI::Range(1, 4096))->capture_default_str();
    s->add_option("--height,-H", o.config.height, "image height")->check(CLI::Range(1, 4096))->capture_default_str();
    s->add_option("--max-depth,-d", o.config.maxDepth, "most scattering events per path")->check(CLI::Range(0, 1024))->capture_default_str();
    s->add_option("--seed", o.config.seed, "random seed")->capture_default_str();
    s->add_option("--threads,-t", o.config.threads, "worker threads, 0 = all cores")->check(CLI::Range(0, 4096))->capture_default_str();
    s->add_option("--heatmap-spp", o.config.heatmapSpp, "spp of the heat maps and crops (default: the middle --spp value)");
    s->add_option("--python", o.config.python, "python3 with matplotlib for the plots (default: /usr/bin/python3, then python3)");
    s->add_flag("--no-plots", o.noPlots, "skip the plots");
    addEstimatorOptions(s, o.config.options, false);
}

int runStudyCommand(StudyOptions& o, const MpiJob& job) {
    o.config.estimators = splitList(o.estimators, estimatorNames(), "--estimators");
    o.config.samplers = splitList(o.samplers, samplerNames(), "--samplers");
    o.config.modes.clear();
    for (const std::string& m : splitList(o.modes, {"branch", "spread"}, "--symmetric-modes")) o.config.modes.push_back(parseSymmetricMode(m));
    o.config.spps = o.spps;
    o.config.splitEstimators = splitList(o.splitEstimators, estimatorNames(), "--split-estimators");
    o.config.plots = !o.noPlots;
    StudyOutcome outcome;
    {
        const LauncherStopGuard guard(job, LauncherStop::StopStudy);
        outcome = runStudyDistributed(job, o.config, &gInterrupted, stderrIsTerminal());
    }
    if (!job.root()) return outcome.cancelled ? 130 : 0;
    if (outcome.cancelled) {
        fmt::print(stderr, "symphong: interrupted; {} finished row(s) kept in {}/results.csv\n", outcome.rows.size(), o.config.outDir);
        return 130;
    }
    fmt::print("{}\n\nreport: {}/report.md ({} rows)\n", outcome.conclusion, o.config.outDir, outcome.rows.size());
    if (o.config.plots && !outcome.plotted) {
        fmt::print(stderr, "symphong: error: the plots could not be made (needs python3 with matplotlib)\n");
        return 1;
    }
    return 0;
}

}  // namespace

int runCli(int argc, const char* const* argv) {
    const MpiJob single(nullptr, nullptr);
    return runCli(argc, argv, single);
}

int runCli(int argc, const char* const* argv, const MpiJob& job) {
    if (!job.root()) std::freopen("/dev/null", "w", stdout);  // help and summaries come from rank 0
    CLI::App app{"symphong: a Phong path tracer built to compare Monte Carlo estimators, symmetric sampling among them."};
    app.require_subcommand(1);
    RenderOptions renderOptions;
    addRenderCommand(app, renderOptions);
    FurnaceOptions furnaceOptions;
    addFurnaceCommand(app, furnaceOptions);
    StudyOptions studyOptions;
    addStudyCommand(app, studyOptions);
    std::string infoScene = "cornell";
    addInfoCommand(app, infoScene);
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        // One line: the problem, then where to read about the command that was being parsed.
        std::string what = e.what();
        for (std::size_t p = what.find('\n'); p != std::string::npos; p = what.find('\n', p)) what.replace(p, 1, "; ");
        std::string command = "symphong";
        for (const CLI::App* sub : app.get_subcommands()) command += " " + sub->get_name();
        if (job.root()) fmt::print(stderr, "symphong: error: {} (see '{} --help')\n", what, command);
        return kBadInput;
    }
    try {
        if (app.got_subcommand("render")) return runRender(renderOptions, job);
        if (app.got_subcommand("study")) return runStudyCommand(studyOptions, job);
        if (app.got_subcommand("info")) return job.root() ? runInfo(infoScene) : 0;
        // The furnace is not shared among ranks (its estimates take seconds): rank 0 runs it alone.
        if (!job.root()) return 0;
        if (job.size() > 1) fmt::print(stderr, "symphong: warning: 'furnace' does not share its work among MPI ranks; rank 0 runs it alone\n");
        if (app.got_subcommand("furnace")) return runFurnaceCommand(furnaceOptions);
    } catch (const InputError& e) {
        // Errors that reach here are the same on every rank (or were agreed on): reported once.
        if (job.root()) fmt::print(stderr, "symphong: error: {}\n", e.what());
        return kBadInput;
    } catch (const std::exception& e) {
        fmt::print(stderr, "symphong: internal error{}: {}\n", job.size() > 1 ? fmt::format(" on rank {}", job.rank()) : "", e.what());
        if (job.size() > 1) job.abort(1);  // the other ranks may be waiting for this one
        return 1;
    }
    return 0;
}

}  // namespace symphong
