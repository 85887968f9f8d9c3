#include "render/progressive.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

namespace symphong {

const char* stopReasonName(StopReason r) {
    switch (r) {
        case StopReason::Spp:
            return "spp";
        case StopReason::Time:
            return "time limit";
        case StopReason::TargetError:
            return "target error";
        case StopReason::Cancelled:
            return "interrupted";
    }
    return "?";
}

double worstRelativeError(const RenderState& state, const std::vector<PixelRect>& regions) {
    if (regions.empty()) return state.regionError({0, 0, state.width, state.height}).relative();
    double worst = 0;
    for (const PixelRect& r : regions) worst = std::max(worst, state.regionError(r).relative());
    return worst;
}

namespace {

/// Why the render stops now, if it does.
bool stopsNow(const StopRules& rules, const RenderState& state, const RenderSettings& settings, double error, StopReason& why) {
    if (settings.cancel && settings.cancel->load()) return why = StopReason::Cancelled, true;
    if (state.finished()) return why = StopReason::Spp, true;
    if (rules.targetError > 0 && state.samplesReached() >= rules.minSppForError && error <= rules.targetError)
        return why = StopReason::TargetError, true;
    if (rules.timeLimit > 0 && state.seconds >= rules.timeLimit) return why = StopReason::Time, true;
    return false;
}

/// Samples per pixel of the next pass: about rules.passSeconds of work, no more than the samples the
/// target error is expected to need (the error falls as 1/sqrt(n)) or the time left allows, at least 1.
/// An explicit pass size (rules.passSpp) is kept as given.
std::uint32_t nextPassSize(const StopRules& rules, const RenderState& state, double secondsPerSpp, double error) {
    const std::uint32_t reached = state.samplesReached(), left = state.sppBound - reached;
    if (rules.passSpp > 0) return std::min(left, rules.passSpp);
    double n = secondsPerSpp > 0 ? rules.passSeconds / secondsPerSpp : 1.0;
    if (rules.targetError > 0) {
        // Up to the samples the error estimate is trusted from; then no more than the estimate says are
        // needed, and at most doubling the count (the estimate is noisy while the count is small).
        if (reached < rules.minSppForError || !std::isfinite(error)) {
            n = std::min<double>(n, std::max(rules.minSppForError, 2 * reached) - reached);
        } else {
            const double needed = reached * (error / rules.targetError) * (error / rules.targetError);
            n = std::min({n, std::ceil(1.05 * needed) - reached, static_cast<double>(reached)});
        }
    }
    if (rules.timeLimit > 0 && secondsPerSpp > 0) n = std::min(n, std::floor((rules.timeLimit - state.seconds) / secondsPerSpp));
    if (!(n >= 1)) n = 1;
    return static_cast<std::uint32_t>(std::min<double>(left, n));
}

}  // namespace

StopReason renderProgressive(const Scene& scene, const Accel& accel, const Estimator& estimator, const RenderSettings& settings,
                             const StopRules& rules, RenderState& state, const std::function<void(const PassReport&)>& afterPass,
                             std::atomic<std::uint64_t>* progress, const PassRunner& runPass) {
    double error = worstRelativeError(state, rules.regions);
    StopReason why = StopReason::Spp;
    if (stopsNow(rules, state, settings, error, why)) return why;
    std::uint32_t pass = rules.passSpp > 0 ? std::min(rules.passSpp, state.sppBound) : 1;
    std::unique_ptr<PathTracer> tracer;  // one for every pass (render/renderer.h makeTracer)
    for (;;) {
        const std::uint32_t from = state.samplesReached(), upTo = std::min(state.sppBound, from + pass);
        const double before = state.seconds;
        if (runPass)
            runPass(state, upTo);
        else {
            if (!tracer) tracer = makeTracer(scene, accel, estimator, settings, state);
            renderSamples(*tracer, estimator, settings, state, upTo, progress);
        }
        const double secondsPerSpp = (state.seconds - before) / std::max<std::uint32_t>(1, upTo - from);
        error = worstRelativeError(state, rules.regions);
        PassReport report;
        report.samplesReached = state.samplesReached();
        report.error = error;
        report.seconds = state.seconds;
        report.last = stopsNow(rules, state, settings, error, why);
        report.reason = why;
        if (!report.last) {
            pass = nextPassSize(rules, state, secondsPerSpp, error);
            report.nextPassSeconds = pass * secondsPerSpp;
        }
        if (afterPass) afterPass(report);
        if (report.last) return why;
    }
}

}  // namespace symphong
