#include "render/long_render.h"

#include "io/files.h"
#include "io/input_error.h"
#include "render/progress.h"

#include <fmt/format.h>

#include <filesystem>

namespace symphong {

namespace {

/// The state to start from: the checkpoint's when resuming from one, else an empty one.
RenderState startingState(const RenderOptions& o, const std::string& path, const RenderIdentity& identity,
                          const std::function<void(const std::string&)>& say) {
    RenderState state(o.width, o.height, o.spp);
    if (path.empty()) return state;
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) {
        if (o.resume) say(fmt::format("no checkpoint at {} yet: starting from the beginning", path));
        checkCanCreate(path);
        return state;
    }
    if (!o.resume)
        throw InputError(
            fmt::format("{}: a checkpoint is already there: add --resume to continue from it, or delete it to start again", path));
    RenderIdentity saved;
    readCheckpoint(path, saved, state);
    requireSameRender(path, saved, identity);
    say(fmt::format("resuming from {}: {} of {} spp, {} rendered", path, state.samplesReached(), state.sppBound,
                    ProgressBar::formatDuration(state.seconds)));
    return state;
}

}  // namespace

LongRender startLongRender(const RenderOptions& o, const Scene& scene, const std::string& checkpoint,
                           const std::function<void(const std::string&)>& say) {
    stopRules(o);  // its input errors first
    LongRender run;
    run.identity = {o.scene, sceneFingerprint(scene, o.scene), schema::pixelSettingsJson(o, renderSchema())};
    run.state = startingState(o, checkpoint, run.identity, say);
    run.secondsBefore = run.state.seconds;
    run.raysBefore = run.state.rays;
    return run;
}

void continueLongRender(LongRender& run, const RenderOptions& o, const Scene& scene, const Accel& accel, const Estimator& estimator,
                        const std::string& checkpoint, const std::atomic<bool>* cancel, std::atomic<std::uint64_t>* progress,
                        const std::function<void(const RenderState&)>& onCheckpoint, const PassRunner& runPass) {
    const StopRules rules = stopRules(o);
    if (progress) progress->store(run.state.samples);  // every sample a tile holds is counted there
    RenderSettings settings = renderSettings(o);
    settings.cancel = cancel;
    CheckpointSchedule schedule(o.checkpointInterval, run.state.seconds);
    bool saved = false;
    const auto save = [&] {
        writeCheckpoint(checkpoint, run.identity, run.state);
        schedule.written(run.state.seconds);
        if (onCheckpoint) onCheckpoint(run.state);
        saved = true;
    };
    run.why = renderProgressive(
        scene, accel, estimator, settings, rules, run.state,
        [&](const PassReport& r) {
            saved = false;
            if (!checkpoint.empty() && schedule.due(r.seconds, r.nextPassSeconds, r.last)) save();
        },
        progress, runPass);
    if (!saved && !checkpoint.empty()) save();  // a render that needed no pass (finished, or its error reached)
    run.error = worstRelativeError(run.state, rules.regions);
}

LongRender renderLong(const RenderOptions& o, const Scene& scene, const Accel& accel, const Estimator& estimator,
                      const std::string& checkpoint, const std::atomic<bool>* cancel, std::atomic<std::uint64_t>* progress,
                      const std::function<void(const RenderState&)>& onCheckpoint, const std::function<void(const std::string&)>& say) {
    LongRender run = startLongRender(o, scene, checkpoint, say);
    continueLongRender(run, o, scene, accel, estimator, checkpoint, cancel, progress, onCheckpoint);
    return run;
}

}  // namespace symphong
