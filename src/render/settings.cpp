#include "render/settings.h"

#include "estimators/options.h"
#include "io/input_error.h"
#include "sampling/sampler_registry.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace symphong {

void checkSamplerName(const std::string& name) {
    if (!findSampler(name))
        throw std::invalid_argument(fmt::format("unknown sampler '{}' (valid: {})", name, fmt::join(samplerNames(), ", ")));
}

namespace {

/// --splitting's names: auto, then the modes' (splitting/ears.h).
std::vector<std::string> renderSplittingNames() {
    std::vector<std::string> names{std::string(kAutoSplitting)};
    names.insert(names.end(), splittingNames().begin(), splittingNames().end());
    return names;
}

void checkRenderSplittingName(const std::string& name) {
    const std::vector<std::string> names = renderSplittingNames();
    if (std::find(names.begin(), names.end(), name) == names.end())
        throw std::invalid_argument(fmt::format("unknown splitting '{}' (valid: {})", name, fmt::join(names, ", ")));
}

std::string splittingHelp() {
    return fmt::format(
        "continuations per path vertex: auto (the default: ears, but none with --split K > 1, with --joint-first-bounce or "
        "below {} spp, too few samples for its learning to pay), none (one, Russian roulette by throughput), ears "
        "(efficiency-aware Russian roulette and splitting, Rath et al. 2022: factors learned per region of the scene from the "
        "render's own earlier samples, at every vertex; docs/estimators.md) or ears-orbit (the same, a first hit's 2, 4 or 8 "
        "continuations one orbit of symmetric copies, symmetric-mix's; needs --estimator phong)",
        kAutoSplittingMinSpp);
}

/// Passes, stop rules and checkpoints: none of them changes a pixel's value, only how many samples are
/// taken (docs/rendering.md "Long renders").
void addProgressiveFields(schema::Schema<RenderOptions>& s) {
    using F = schema::Field<RenderOptions>;
    using schema::member;
    s.push_back(F("time", "--time",
                  "stop after the pass in flight once the render has taken this many seconds (earlier runs of a "
                  "resumed render included); 0: no limit",
                  member(&RenderOptions::time))
                    .range(0, 1e9)
                    .keepsPixels());
    s.push_back(F("target_error", "--target-error",
                  "stop once the relative standard error of the image's mean luminance (or of each --target-region's) is at most "
                  "this, e.g. 0.01; 0: none. --spp stays the upper bound",
                  member(&RenderOptions::targetError))
                    .range(0, 1)
                    .keepsPixels());
    s.push_back(F("target_region", "--target-region",
                  "X,Y,W,H: a rectangle of pixels whose mean --target-error applies to (repeat the option for more; the whole image "
                  "when none)",
                  member(&RenderOptions::targetRegions))
                    .range(0, 16384)
                    .noDefaultShown()
                    .keepsPixels());
    s.push_back(F("pass_spp", "--pass-spp",
                  "samples per pixel in each pass (0: passes of about 2 s, shorter when checkpoints are frequent)",
                  member(&RenderOptions::passSpp))
                    .range(0, 1000000)
                    .keepsPixels());
    s.push_back(F("checkpoint", "--checkpoint",
                  "write the render's state to this file every --checkpoint-interval seconds, at the end and when stopped by "
                  "SIGINT or SIGTERM (default with --resume: the output's name + .ckpt)",
                  member(&RenderOptions::checkpoint))
                    .only(schema::kCli | schema::kPython)
                    .noDefaultShown()
                    .keepsPixels());
    s.push_back(F("checkpoint_interval", "--checkpoint-interval", "seconds of render time between checkpoints",
                  member(&RenderOptions::checkpointInterval))
                    .mustBePositive()
                    .only(schema::kCli | schema::kPython)
                    .keepsPixels());
    s.push_back(F("resume", "--resume",
                  "continue from the checkpoint if there is one (the image is bit for bit the uninterrupted render's); start "
                  "from the beginning if there is none",
                  member(&RenderOptions::resume))
                    .only(schema::kCli | schema::kPython)
                    .keepsPixels());
}

}  // namespace

const schema::Schema<RenderOptions>& renderSchema() {
    using F = schema::Field<RenderOptions>;
    using schema::member;
    static const schema::Schema<RenderOptions> fields = [] {
        schema::Schema<RenderOptions> s;
        s.push_back(F("scene", "scene", "cornell, FILE.obj, FILE.gltf/.glb/.ply/.fbx/.dae/.3ds or FILE.json", member(&RenderOptions::scene))
                        .only(schema::kCli | schema::kJson)
                        .keepsPixels());
        s.push_back(F("estimator", "--estimator,-e",
                      "reflected-radiance estimator: " + fmt::format("{}", fmt::join(estimatorNames(), ", ")),
                      member(&RenderOptions::estimator)));
        s.push_back(F("sampler", "--sampler", "sample generator: " + fmt::format("{}", fmt::join(samplerNames(), ", ")),
                      member(&RenderOptions::sampler))
                        .namedFrom(samplerNames)
                        .checkedBy(checkSamplerName));
        s.push_back(F("spp", "--spp,-s", "camera samples per pixel", member(&RenderOptions::spp)).range(1, 1000000));
        s.push_back(F("width", "--width,-W", "image width in pixels", member(&RenderOptions::width)).range(1, 16384));
        s.push_back(F("height", "--height,-H", "image height in pixels", member(&RenderOptions::height)).range(1, 16384));
        s.push_back(F("max_depth", "--max-depth,-d", "most scattering events per path (0: emitters only)", member(&RenderOptions::maxDepth))
                        .range(0, 1024));
        s.push_back(F("seed", "--seed", "random seed", member(&RenderOptions::seed)));
        s.push_back(
            F("threads", "--threads,-t", "worker threads, 0 = all cores", member(&RenderOptions::threads)).range(0, 4096).keepsPixels());
        s.push_back(F("output", "--output,-o", "output image, .png or .exr (default: out/<scene-name>.png)", member(&RenderOptions::output))
                        .only(schema::kCli)
                        .noDefaultShown()
                        .keepsPixels());
        s.push_back(F("exposure", "--exposure", "linear scale applied before PNG clamping", member(&RenderOptions::exposure))
                        .mustBePositive()
                        .only(schema::kCli | schema::kJson)
                        .keepsPixels());
        s.push_back(F("exr_half", "--exr-half", "write EXR as 16-bit half instead of 32-bit float", member(&RenderOptions::exrHalf))
                        .only(schema::kCli | schema::kJson)
                        .keepsPixels());
        s.push_back(F("variance_output", "--variance-output",
                      "also write the per-pixel variance of the mean (sample variance / spp, per channel) as a 32-bit EXR: "
                      "`symphong compare --variance` gives the bias its standard error with it",
                      member(&RenderOptions::varianceOutput))
                        .only(schema::kCli)
                        .noDefaultShown()
                        .keepsPixels());
        s.push_back(F("split", "--split",
                      "first-hit splitting: trace K directions per camera sample from its first hit (K calls of the estimator on "
                      "sub-samples of the pixel's pattern, each weighted 1/K)",
                      member(&RenderOptions::split))
                        .range(1, 64));
        s.push_back(F("splitting", "--splitting", splittingHelp(), member(&RenderOptions::splitting))
                        .namedFrom(renderSplittingNames)
                        .checkedBy(checkRenderSplittingName));
        s.push_back(F("first_bounce_stream", "--first-bounce-stream",
                      "give the first hit's estimator other random numbers (stream S), every other decision of the path keeping its "
                      "own: renders that differ only in S measure the first bounce's share of the variance (docs/estimators.md)",
                      member(&RenderOptions::firstBounceStream))
                        .range(0, 1000000));
        s.push_back(F("joint_first_bounce", "--joint-first-bounce",
                      "sobol: the pixel position and the first bounce's direction from one 4D Owen-scrambled Sobol' pattern instead of "
                      "two independently matched pairs (off by default: it lowers MSE for cosine but not for every estimator, "
                      "docs/sampling.md)",
                      member(&RenderOptions::jointFirstBounce)));
        s.push_back(F("no_nee", "--no-nee",
                      "no light sampling of emissive triangles: they are found only by the estimator's directions (point, spot and "
                      "directional lights are still sampled: nothing else can reach them)",
                      member(&RenderOptions::noNee))
                        .python("nee", true));
        s.push_back(F("bump_shadowing", "--bump-shadowing",
                      "where a normal or bump map bends the shading normal, dim the light that the bent normal faces more than the "
                      "surface does (the shadowing term of Chiang et al. 2019, as Blender Cycles does; docs/scene-format.md)",
                      member(&RenderOptions::bumpShadowing)));
        for (auto& f : schema::nested(estimatorOptionsSchema(), &RenderOptions::estimatorOptions)) s.push_back(std::move(f));
        addProgressiveFields(s);
        return s;
    }();
    return fields;
}

void applySceneSettings(RenderOptions& o, const Scene& scene, const std::string& spec, const std::set<std::string>& given) {
    if (scene.renderSettings.empty()) return;
    nlohmann::json settings = nlohmann::json::parse(scene.renderSettings);
    nlohmann::json taken = nlohmann::json::object();
    for (auto it = settings.begin(); it != settings.end(); ++it) {
        if (it.key() == "scene") throw InputError(fmt::format("{}: \"render\": a scene file cannot name another scene", spec));
        if (!given.count(it.key())) taken[it.key()] = it.value();
    }
    try {
        schema::fromJson(taken, o, renderSchema());
    } catch (const std::invalid_argument& e) {
        throw InputError(fmt::format("{}: \"render\": {}", spec, e.what()));
    }
}

void finishRenderOptions(RenderOptions& o, const Scene& scene, const std::string& spec, const std::set<std::string>& given) {
    applySceneSettings(o, scene, spec, given);
    checkRenderOptions(o);
    resolveSplitting(o);
}

void checkRenderOptions(const RenderOptions& o) {
    if (static_cast<long>(o.width) * o.height > kMaxImagePixels)
        throw InputError(fmt::format("image size {}x{} is too large (at most {} pixels)", o.width, o.height, kMaxImagePixels));
    requireImageMemory(o.width, o.height);
    if (!std::isfinite(o.exposure)) throw InputError(fmt::format("--exposure {} is not finite", o.exposure));
    const SplittingMode splitting = effectiveSplitting(o);  // auto or a name the schema checked
    if (learnsFactors(splitting) && o.split > 1)
        throw InputError(fmt::format("--split {} and --splitting {}: ears decides the first hit's splitting itself; give one of them",
                                     o.split, o.splitting));
    if (learnsFactors(splitting) && o.jointFirstBounce)
        throw InputError(fmt::format(
            "--joint-first-bounce and --splitting {}: a split first hit reads sub-samples, which have no joint pattern", o.splitting));
    if (splitting == SplittingMode::EarsOrbit && o.estimator != "phong")
        throw InputError(
            fmt::format("--splitting ears-orbit needs --estimator phong (got '{}'): the orbit's copies have phong's density, "
                        "which the light-sampling weights at the vertex assume",
                        o.estimator));
}

StopRules stopRules(const RenderOptions& o) {
    StopRules rules;
    rules.timeLimit = o.time;
    rules.targetError = o.targetError;
    rules.passSpp = o.passSpp;
    if (o.targetRegions.size() % 4 != 0)
        throw InputError(fmt::format("--target-region: {} numbers; each region is four (X,Y,W,H)", o.targetRegions.size()));
    for (std::size_t i = 0; i < o.targetRegions.size(); i += 4) {
        const PixelRect r{o.targetRegions[i], o.targetRegions[i + 1], o.targetRegions[i + 2], o.targetRegions[i + 3]};
        if (r.width < 1 || r.height < 1 || r.x + r.width > o.width || r.y + r.height > o.height)
            throw InputError(fmt::format("--target-region {},{},{},{}: not a non-empty rectangle inside the {}x{} image", r.x, r.y, r.width,
                                         r.height, o.width, o.height));
        rules.regions.push_back(r);
    }
    if (!o.targetRegions.empty() && !(o.targetError > 0))
        throw InputError("--target-region needs --target-error (the error its mean must reach)");
    if (!o.checkpoint.empty() || o.resume) rules.passSeconds = std::min(rules.passSeconds, o.checkpointInterval / 4);
    return rules;
}

SplittingMode effectiveSplitting(const RenderOptions& o) {
    if (o.splitting != kAutoSplitting) return splittingMode(o.splitting);
    const bool learns = o.split <= 1 && !o.jointFirstBounce && o.spp >= kAutoSplittingMinSpp;
    return learns ? SplittingMode::Ears : SplittingMode::None;
}

void resolveSplitting(RenderOptions& o) { o.splitting = splittingName(effectiveSplitting(o)); }

RenderSettings renderSettings(const RenderOptions& o) {
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
    settings.trace.bumpShadowing = o.bumpShadowing;
    settings.trace.splitting = effectiveSplitting(o);
    return settings;
}

}  // namespace symphong
