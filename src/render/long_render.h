// render/long_render.h — a render in passes with its checkpoint, as `symphong render` and the Python
// module's render() run it when a stop rule, a pass size or a checkpoint is asked for: the starting state
// (the checkpoint's when resuming, after checking that it is this render's), the passes
// (render/progressive.h) and a checkpoint whenever the schedule says so, at the end and when cancelled.
#pragma once

#include "accel/accel.h"
#include "render/checkpoint.h"
#include "render/progressive.h"
#include "render/settings.h"

#include <atomic>
#include <functional>
#include <string>

namespace symphong {

struct LongRender {
    RenderIdentity identity;
    RenderState state;
    StopReason why = StopReason::Spp;
    double error = 0;          ///< relative standard error of the mean (worst region) at the end
    double secondsBefore = 0;  ///< render time already in the checkpoint it resumed from
    std::uint64_t raysBefore = 0;
};

/// The start of a render in passes: its state (the checkpoint's when `checkpoint` exists and o.resume,
/// after checking that it is this render's; an existing one without o.resume is an InputError), its
/// identity and the time and rays already in it. `say` receives the messages for the user (resuming,
/// starting afresh).
LongRender startLongRender(const RenderOptions& o, const Scene& scene, const std::string& checkpoint,
                           const std::function<void(const std::string&)>& say);

/// Runs the passes of a started render until a rule stops it, writing the checkpoint (when `checkpoint`
/// is not empty) whenever the schedule says so, at the end and when cancelled; `onCheckpoint` is called
/// after each (the command line writes its preview image there). `cancel` stops it after the tiles in
/// flight. `runPass` renders a pass (default: this process alone).
void continueLongRender(LongRender& run, const RenderOptions& o, const Scene& scene, const Accel& accel, const Estimator& estimator,
                        const std::string& checkpoint, const std::atomic<bool>* cancel, std::atomic<std::uint64_t>* progress,
                        const std::function<void(const RenderState&)>& onCheckpoint, const PassRunner& runPass = nullptr);

/// startLongRender, then continueLongRender in this process.
LongRender renderLong(const RenderOptions& o, const Scene& scene, const Accel& accel, const Estimator& estimator,
                      const std::string& checkpoint, const std::atomic<bool>* cancel, std::atomic<std::uint64_t>* progress,
                      const std::function<void(const RenderState&)>& onCheckpoint, const std::function<void(const std::string&)>& say);

}  // namespace symphong
