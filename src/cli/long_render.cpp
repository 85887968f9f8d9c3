// `symphong render` in passes (render/progressive.h): stop rules (--time, --target-error), checkpoints
// (render/checkpoint.h) with a preview image at each, --resume, and SIGINT/SIGTERM that stop the render
// after the tiles in flight and keep its state and image.
#include "render/long_render.h"
#include "accel/accel.h"
#include "cli/commands.h"
#include "cli/interrupts.h"
#include "distrib/mpi_job.h"
#include "distrib/render.h"
#include "estimators/estimator.h"
#include "io/files.h"
#include "io/image.h"
#include "io/input_error.h"
#include "render/progress.h"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <csignal>

namespace symphong {

namespace {

/// The checkpoint to use: --checkpoint, else with --resume the output's name + ".ckpt", else none.
std::string checkpointPath(const RenderOptions& o, const std::string& output) {
    if (!o.checkpoint.empty()) return o.checkpoint;
    return o.resume ? output + ".ckpt" : std::string();
}

std::string stopText(StopReason why, const RenderOptions& o) {
    switch (why) {
        case StopReason::Spp:
            return "all";
        case StopReason::Time:
            return fmt::format("time limit {} s", o.time);
        case StopReason::TargetError:
            return fmt::format("target error {:.3g}% reached", 100 * o.targetError);
        case StopReason::Cancelled:
            return fmt::format("interrupted by {}", gInterruptSignal.load() == SIGTERM ? "SIGTERM" : "SIGINT");
    }
    return stopReasonName(why);
}

}  // namespace

int renderInPasses(const RenderOptions& o, const Scene& scene, const Estimator& estimator, const std::string& output, const MpiJob& job) {
    const std::string path = checkpointPath(o, output);
    // Rank 0 starts the render (reads the checkpoint); every rank learns whether that worked.
    LongRender run;
    std::string error;
    try {
        if (job.root())
            run = startLongRender(o, scene, path, [](const std::string& message) { fmt::print(stderr, "symphong: {}\n", message); });
        else
            stopRules(o);
    } catch (const InputError& e) {
        if (!job.active()) throw;
        error = e.what();
    }
    error = job.firstError(error);
    if (!error.empty()) throw InputError(error);
    const Accel accel(scene);
    RenderSettings settings = renderSettings(o);
    settings.cancel = &gInterrupted;
    const LauncherStopGuard guard(job, LauncherStop::StopRender);
    if (!job.root()) {
        followPasses(job, scene, accel, estimator, settings);
        return 0;
    }
    std::atomic<std::uint64_t> done{0};
    {
        ProgressBar bar(done, static_cast<std::uint64_t>(o.width) * o.height * o.spp, "samples", stderrIsTerminal());
        try {
            continueLongRender(
                run, o, scene, accel, estimator, path, &gInterrupted, &done,
                [&](const RenderState& state) { writeImage(state.image(), output, o.exposure, o.exrHalf); },  // the preview
                leadPasses(job, scene, accel, estimator, settings, &done));
        } catch (const InputError& e) {  // a checkpoint or preview that cannot be written: the others wait for rank 0
            if (job.size() == 1) throw;
            fmt::print(stderr, "symphong: error: {}\n", e.what());
            job.abort(kBadInput);
        }
        endPasses(job);
        bar.finish();
    }
    const RenderState& state = run.state;
    if (path.empty()) writeImage(state.image(), output, o.exposure, o.exrHalf);
    if (!o.varianceOutput.empty()) writeExr(state.variance(), o.varianceOutput);
    if (state.badSamples > 0) fmt::print(stderr, "symphong: warning: {} non-finite path contributions were discarded\n", state.badSamples);
    const double runSeconds = std::max(state.seconds - run.secondsBefore, 1e-9);
    fmt::print(
        "{}: {}x{}, {} of {} spp ({}), relative error of the mean {:.3g}%, estimator {}, sampler {}, splitting {}{}: "
        "{:.2f} s{}, {:.2f} Mrays/s{} -> {}\n",
        scene.name, o.width, o.height, state.samplesReached(), o.spp, stopText(run.why, o), 100 * run.error, estimator.name(),
        effectiveSampler(estimator, o.sampler), o.splitting, job.size() > 1 ? fmt::format(", {} ranks", job.size()) : "", state.seconds,
        run.secondsBefore > 0 ? fmt::format(" ({:.2f} s in this run)", state.seconds - run.secondsBefore) : "",
        static_cast<double>(state.rays - run.raysBefore) / runSeconds / 1e6, path.empty() ? "" : ", checkpoint " + path, output);
    if (run.why != StopReason::Cancelled) return 0;
    if (path.empty())
        fmt::print(stderr, "symphong: stopped at {} spp; the image so far is in {} (without --checkpoint it cannot be resumed)\n",
                   state.samplesReached(), output);
    else
        fmt::print(stderr, "symphong: stopped at {} spp; the same command with --resume continues from {}\n", state.samplesReached(), path);
    return 128 + (gInterruptSignal.load() ? gInterruptSignal.load() : SIGINT);
}

}  // namespace symphong
