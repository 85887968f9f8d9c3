// render/progressive.h — a render in passes over the whole image, and the rules that stop it: the spp
// bound, a time limit, a target relative error of the image mean (or of each chosen region's mean), or a
// cancellation. Each pass takes every tile to the next sample count (render/renderer.h renderSamples),
// so the image after any sequence of passes is the one-pass image at that count, bit for bit. After each
// pass a callback sees the state (the command line writes checkpoints and previews there).
#pragma once

#include "render/renderer.h"

#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace symphong {

struct StopRules {
    double timeLimit = 0;              ///< seconds of render time in all (earlier runs included); 0: none
    double targetError = 0;            ///< relative standard error of the mean; 0: none
    std::vector<PixelRect> regions;    ///< empty: the whole image's mean; else each region's
    std::uint32_t passSpp = 0;         ///< samples per pixel in a pass; 0: chosen from the time a pass takes
    double passSeconds = 2.0;          ///< what an automatic pass aims to take
    std::uint32_t minSppForError = 4;  ///< the error estimate is trusted from this many samples on
};

enum class StopReason { Spp, Time, TargetError, Cancelled };
const char* stopReasonName(StopReason r);

struct PassReport {
    std::uint32_t samplesReached = 0;  ///< every tile has at least this many samples
    double error = 0;                  ///< the largest relative error over the regions (or the image)
    double seconds = 0;                ///< render time so far, earlier runs included
    double nextPassSeconds = 0;        ///< what the next pass is expected to take (0 after the last)
    bool last = false;                 ///< the render stops after this pass
    StopReason reason = StopReason::Spp;
};

/// The largest relative standard error of the mean over `regions` (the whole image when empty).
double worstRelativeError(const RenderState& state, const std::vector<PixelRect>& regions);

/// What renders one pass: takes every tile of the state to `upTo` samples (renderSamples, or a render
/// shared with other processes, distrib/render.h).
using PassRunner = std::function<void(RenderState& state, std::uint32_t upTo)>;

/// Renders passes into `state` until a rule stops it (the spp bound is state.sppBound). A state that is
/// already finished returns at once (reason Spp). `afterPass` is called after every pass, the last
/// included, on the calling thread. `runPass` renders each pass (default: renderSamples in this process).
StopReason renderProgressive(const Scene& scene, const Accel& accel, const Estimator& estimator, const RenderSettings& settings,
                             const StopRules& rules, RenderState& state, const std::function<void(const PassReport&)>& afterPass,
                             std::atomic<std::uint64_t>* progress = nullptr, const PassRunner& runPass = nullptr);

}  // namespace symphong
