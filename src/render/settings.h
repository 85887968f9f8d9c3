// render/settings.h — what a render is asked for (RenderOptions), as `symphong render` and the Python
// module's render() take it, described once by its schema: each field's name, flag, default (the member
// initialisers below), range and help. The command line builds its options from renderSchema(), the
// Python module its keyword arguments and docstring; checkRenderOptions() holds the checks that span
// fields, and renderSettings() turns the options into the renderer's settings.
#pragma once

#include "estimators/estimator.h"
#include "render/progressive.h"
#include "render/renderer.h"
#include "util/schema.h"

#include "scene/scene.h"

#include <cstdint>
#include <set>
#include <string>
#include <string_view>
#include <vector>

namespace symphong {

/// `--splitting auto`, the default: ears where a render can learn, else none (effectiveSplitting).
inline constexpr std::string_view kAutoSplitting = "auto";
/// The fewest samples a pixel with which `auto` learns: below them EARS's learning (its probe, the epochs that
/// record, its table) is not paid back. Against plain phong at 128x96 (scripts/ears-study.sh, five scenes): at 8
/// spp 0.71x-0.81x on all but the smooth sky (2.27x), at 16 0.83x-0.89x, at 32 0.90x-0.93x (the default box
/// 1.11x); at 64 the ties 0.95x-0.98x, the default box 1.08x (docs/performance.md "EARS as the default").
inline constexpr std::uint32_t kAutoSplittingMinSpp = 64;

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
    std::string varianceOutput;  ///< EXR of the per-pixel variance of the mean, for `symphong compare --variance`
    bool noNee = false;
    int split = 1;
    std::string splitting = std::string(kAutoSplitting);  ///< auto (effectiveSplitting), or a splittingNames() entry
    std::uint32_t firstBounceStream = 0;
    bool jointFirstBounce = false;
    bool bumpShadowing = false;
    EstimatorOptions estimatorOptions;
    // Progressive rendering (render/progressive.h, render/checkpoint.h).
    double time = 0;
    double targetError = 0;
    std::vector<int> targetRegions;  ///< x, y, width, height of each region, flattened
    std::uint32_t passSpp = 0;
    std::string checkpoint;
    double checkpointInterval = 120;
    bool resume = false;

    /// Whether the render goes in passes: a stop rule, a pass size or a checkpoint was asked for.
    bool progressive() const { return time > 0 || targetError > 0 || passSpp > 0 || !checkpoint.empty() || resume; }
};

/// Every field of RenderOptions, in the order `symphong render --help` lists them.
const schema::Schema<RenderOptions>& renderSchema();

/// Checks that span fields or need the machine: the image's size (at most kMaxImagePixels, and its
/// memory) and a finite exposure. Throws InputError.
void checkRenderOptions(const RenderOptions& o);

/// The splitting a render of these options uses: the named one, or for `auto` (the default) ears unless
/// --split K > 1 or --joint-first-bounce is given (each is refused beside ears: the user chose the first
/// hit's splitting or its pattern) or the render takes fewer than kAutoSplittingMinSpp samples a pixel (too
/// few for its learning to pay), then none.
/// docs/estimators.md "Efficiency-aware splitting" has the measurements behind the default.
SplittingMode effectiveSplitting(const RenderOptions& o);

/// Writes effectiveSplitting's name over `auto`, so that what the render reports, and what identifies its
/// checkpoint, is the splitting it used. Call after the scene's own settings are applied.
void resolveSplitting(RenderOptions& o);

/// The renderer's settings for these options.
RenderSettings renderSettings(const RenderOptions& o);

/// The stop rules of these options (render/progressive.h); checks the regions against the image
/// (InputError naming the region).
StopRules stopRules(const RenderOptions& o);

/// The scene's own render settings (a JSON scene's "render" object, Scene::renderSettings) under the
/// options the user gave (`given`: their schema keys): each setting the user did not give is read from
/// the scene. A setting that is unknown, of the wrong type or out of range is an InputError naming the
/// scene file ("scene.json: \"render\": spp: out of range (got 0)").
void applySceneSettings(RenderOptions& o, const Scene& scene, const std::string& spec, const std::set<std::string>& given);

/// The options a render of `scene` runs with, as every front end (the command line, Python's render() and
/// Progressive) makes them once the scene is loaded: the scene's own settings under the given ones
/// (applySceneSettings), the checks (checkRenderOptions), then `auto` resolved (resolveSplitting), in that
/// order, since the rule of `auto` reads the spp and the first hit's options that the scene may set.
void finishRenderOptions(RenderOptions& o, const Scene& scene, const std::string& spec, const std::set<std::string>& given);

/// Throws std::invalid_argument "unknown sampler 'x' (valid: ...)" unless `name` is a sampler.
void checkSamplerName(const std::string& name);

}  // namespace symphong
