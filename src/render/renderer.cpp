#include "render/renderer.h"

#include "io/memory.h"
#include "sampling/sampler_registry.h"
#include "sampling/sobol_lanes.h"
#include "util/cpu_time.h"

#include <fmt/format.h>
#include <oneapi/tbb/enumerable_thread_specific.h>
#include <oneapi/tbb/global_control.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_arena.h>
#include <oneapi/tbb/task_group.h>
#include <oneapi/tbb/version.h>

#include <array>
#include <chrono>
#include <cmath>
#include <memory>
#include <mutex>
#include <optional>

namespace symphong {

void requireImageMemory(int width, int height) {
    const std::uint64_t pixels =
        saturatingMultiply(static_cast<std::uint64_t>(std::max(0, width)), static_cast<std::uint64_t>(std::max(0, height)));
    requireMemory(saturatingMultiply(pixels, kImageBytesPerPixel), fmt::format("image size {}x{}", width, height));
}

int tileCount(int width, int height) { return ((width + kRenderTile - 1) / kRenderTile) * ((height + kRenderTile - 1) / kRenderTile); }

void tileRect(int tile, int width, int height, int& x0, int& y0, int& x1, int& y1) {
    const int tilesX = (width + kRenderTile - 1) / kRenderTile;
    x0 = (tile % tilesX) * kRenderTile, y0 = (tile / tilesX) * kRenderTile;
    x1 = std::min(width, x0 + kRenderTile), y1 = std::min(height, y0 + kRenderTile);
}

CameraRays::CameraRays(const Camera& cam, int w, int h)
    : position(cam.position),
      forward(normalize(cam.target - cam.position)),
      right(normalize(cross(forward, cam.up))),
      up(cross(right, forward)),
      tanHalf(std::tan(0.5 * cam.fovY * kPi / 180.0)),
      aspect(static_cast<double>(w) / h),
      width(w),
      height(h) {}

void cameraRay(const Camera& cam, int width, int height, double px, double py, Vec3& origin, Vec3& dir) {
    CameraRays(cam, width, height)(px, py, origin, dir);
}

namespace {

/// A thread hands its continuations' records to the epoch's sums when it holds this many (and at the end
/// of each tile): few enough to stay in the core's cache (256 KiB).
constexpr std::size_t kRecordsPerFlush = 8192;

/// The tracer's settings for a render: its own, with --splitting ears's roulette floored at plain
/// roulette's (TraceSettings::earsRouletteFloor) when the sampler is a low-discrepancy one (or as
/// RenderSettings::earsRouletteFloor forces it).
TraceSettings traceSettings(const Estimator& estimator, const RenderSettings& settings) {
    TraceSettings trace = settings.trace;
    trace.earsRouletteFloor = settings.earsRouletteFloor.value_or(!isIndependentSampler(effectiveSampler(estimator, settings.sampler)));
    return trace;
}

/// Camera sample i of the pixel at (x, y) (`pixel` its index): its stream, past its jitter inside the pixel,
/// and its camera ray o + t d.
SampleStream cameraSample(const Sampler& sampler, const CameraRays& cameraRays, int x, int y, std::size_t pixel, std::uint32_t i, Vec3& o,
                          Vec3& d) {
    SampleStream samples(sampler, pixel, i, SampleDimensions::kPixel);
    const Point2 jitter = samples.get2D();
    cameraRays(x + jitter.u, y + jitter.v, o, d);
    return samples;
}

/// A camera sample's radiance as the image takes it: one that is not finite or has a negative channel is
/// counted in stats.badSamples and comes back black (never written).
Color keptRadiance(const Color& L, TraceStats& stats) {
    if (isFinite(L) && minComponent(L) >= 0) return L;
    ++stats.badSamples;
    return Color(0.0);
}

/// Camera sample i of the pixel at (x, y) traced alone: the radiance along its camera ray, as kept.
Color traceCameraSample(const PathTracer& tracer, const Sampler& sampler, const CameraRays& cameraRays, int x, int y, std::size_t pixel,
                        std::uint32_t i, TraceStats& stats, PathScratch& scratch) {
    Vec3 o, d;
    SampleStream samples = cameraSample(sampler, cameraRays, x, y, pixel, i, o, d);
    return keptRadiance(tracer.cameraRadiance(o, d, samples, stats, scratch), stats);
}

/// A tile's camera samples gathered into batches of PathTracer::cameraBatch() camera rays, traced together
/// (PathTracer::cameraRadiances), each radiance added to its pixel's sums in the order of its sample's index: the
/// same sums as traceCameraSample of each in turn. traceSegment gives it one sample index of the tile's pixels
/// at a time, in the tile's order, and flushes after each: a batch holds the same camera samples in any pass
/// (Embree's packets can answer a rare ray according to the other rays in them, so the samples that share them
/// must not depend on the passes for a render in passes to be the one-pass render bit for bit).
class CameraPackets {
public:
    CameraPackets(const PathTracer& tracer, const Sampler& sampler, const CameraRays& cameraRays, RenderState& state, TraceStats& stats,
                  PathScratch& scratch)
        : tracer_(tracer), sampler_(sampler), cameraRays_(cameraRays), state_(state), stats_(stats), scratch_(scratch) {}

    /// Sample i of pixel (x, y), traced when the packet is full or at flush().
    void add(int x, int y, std::size_t pixel, std::uint32_t i) {
        if (jitterInLanes_) {  // its jitter and ray at flush(), with the batch's
            streams_[n_] = SampleStream(sampler_, pixel, i, SampleDimensions::kPixel);
            xs_[n_] = x;
            ys_[n_] = y;
        } else {
            streams_[n_] =
                cameraSample(sampler_, cameraRays_, x, y, pixel, i, origin_, dirs_[n_]);  // origin_: the camera's, the same for all
        }
        pixels_[n_] = pixel;
        if (++n_ == capacity_) flush();
    }
    /// Traces the samples added since the last flush and adds them to their pixels.
    void flush() {
        if (n_ == 0) return;
        if (jitterInLanes_) cameraRaysInLanes();
        tracer_.cameraRadiances(origin_, dirs_.data(), n_, streams_.data(), radiances_.data(), stats_, scratch_);
        for (std::size_t k = 0; k < n_; ++k) {
            const Color L = keptRadiance(radiances_[k], stats_);
            const std::size_t pixel = pixels_[k];
            state_.sum[pixel] += L;
            state_.sumSq[pixel] += L * L;
            state_.sumLuminanceSq[pixel] += luminance(L) * luminance(L);
        }
        n_ = 0;
    }

private:
    /// cameraSample's jitter, rays and streams for the batch's samples, their jitter pairs computed together in the
    /// sampler's lanes (sampling/sobol_lanes.h): the same values.
    void cameraRaysInLanes() {
        std::array<std::uint64_t, kMost> keys;
        std::array<std::uint32_t, kMost> indices;
        for (std::size_t k = 0; k < n_; ++k) {
            keys[k] = streams_[k].pixelKey();
            indices[k] = streams_[k].sampleIndex();
        }
        std::array<double, kMost> us, vs;
        sobolPairValues(keys.data(), indices.data(), sampler_.samplesPerPixel(), SampleDimensions::kPixel, n_, us.data(), vs.data());
        for (std::size_t k = 0; k < n_; ++k) {
            streams_[k].setDimension(SampleDimensions::kPixel + 2);
            cameraRays_(xs_[k] + us[k], ys_[k] + vs[k], origin_, dirs_[k]);
        }
    }

    const PathTracer& tracer_;
    const Sampler& sampler_;
    const CameraRays& cameraRays_;
    RenderState& state_;
    TraceStats& stats_;
    PathScratch& scratch_;
    static constexpr std::size_t kMost = WavefrontBatch::kSize;
    static_assert(kMost >= PathTracer::kCameraPacket);
    std::size_t capacity_ = tracer_.cameraBatch();
    std::array<SampleStream, kMost> streams_;
    std::array<Vec3, kMost> dirs_;
    std::array<std::size_t, kMost> pixels_{};
    std::array<Color, kMost> radiances_;
    const bool jitterInLanes_ = sampler_.isSobol() && sobolLanesAvailable();
    std::array<int, kMost> xs_, ys_;  ///< the samples' pixels, for their rays at flush() (jitterInLanes_)
    Vec3 origin_;
    std::size_t n_ = 0;
};

/// Runs renderTile over every tile (or those settings.tiles gives out) on settings.threads threads.
template <class Fn>
void forEachTile(const RenderSettings& settings, Fn&& renderTile) {
    // --threads N means N threads even above the core count (TBB otherwise caps its workers there).
    std::optional<tbb::global_control> allow;
    if (settings.threads > 0) allow.emplace(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(settings.threads));
    tbb::task_arena arena(settings.threads > 0 ? settings.threads : tbb::task_arena::automatic);
    arena.execute([&] {
        if (!settings.tiles) {
            tbb::parallel_for(0, tileCount(settings.width, settings.height), [&](int tile) { renderTile(tile); });
            return;
        }
        // Tiles from a source: one loop per worker thread, each taking tiles until the source is dry.
        tbb::task_group workers;
        for (int w = 0; w < arena.max_concurrency(); ++w)
            workers.run([&] {
                for (int tile; settings.tiles->next(tile);) renderTile(tile);
            });
        workers.wait();
    });
}

}  // namespace

namespace {

/// Adds the wall and CPU time from its construction to its destruction to the state's (the render's cost).
class CostClock {
public:
    explicit CostClock(RenderState& state) : state_(state), start_(std::chrono::steady_clock::now()), cpuStart_(processCpuSeconds()) {}
    ~CostClock() {
        state_.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
        state_.cpuSeconds += processCpuSeconds() - cpuStart_;
    }
    CostClock(const CostClock&) = delete;
    CostClock& operator=(const CostClock&) = delete;

private:
    RenderState& state_;
    std::chrono::steady_clock::time_point start_;
    double cpuStart_;
};

/// Whether a render's continuations are recorded in the state's epoch: not in the last epoch of the render
/// (the one that reaches its spp), which has no epoch after it to learn from them (the same in every run of
/// this spp, resumed or not).
bool recordsEpoch(const RenderState& state) {
    return state.ears && !state.earsResting() && !ears::lastEpoch(state.ears->epoch, state.sppBound);
}

/// Whether the epoch records the first hit's continuations too: not after epoch 0 of a probed render,
/// whose first-hit factors hold from then on (ears::Learning::advance); the deeper vertices' scale is then
/// sqrt(C / V) at the held factors (ears::learnFactors with no first-hit cells).
bool recordsFirstHit(const RenderState& state) { return recordsEpoch(state) && (!state.ears->probed || state.ears->epoch == 0); }

/// renderSegment with a tracer from makeTracer, its records switched on or off as recordsEpoch says; its
/// time counts in the state's.
void traceSegment(PathTracer& tracer, const Estimator& estimator, const RenderSettings& settings, RenderState& state, std::uint32_t upTo,
                  std::atomic<std::uint64_t>* progress) {
    const CostClock clock(state);
    tracer.setRecords(recordsEpoch(state), recordsFirstHit(state));
    tracer.setResting(state.earsResting());
    const bool learns = learnsFactors(settings.trace.splitting);
    const auto sampler = makeSampler(effectiveSampler(estimator, settings.sampler), state.sppBound, settings.seed);
    upTo = std::min(upTo, state.sppBound);
    const CameraRays cameraRays(tracer.scene().camera, settings.width, settings.height);
    std::mutex statsMutex, learnMutex;
    // The continuations a tile traced, into the epoch's exact sums (the order of tiles does not matter).
    const auto learn = [&](std::vector<ears::Record>& records) {
        if (!learns || records.empty()) return;
        std::lock_guard<std::mutex> lock(learnMutex);
        state.ears->add(records);
        records.clear();
    };
    // One scratch a thread, kept from tile to tile: a fresh one per tile allocated its record buffer anew
    // (hundreds of kilobytes: page faults, dear in a VM, 1.6% of an EARS render's time).
    tbb::enumerable_thread_specific<PathScratch> scratches;

    const auto renderTile = [&](int tile) {
        if (settings.cancel && settings.cancel->load(std::memory_order_relaxed)) return;
        const std::uint32_t from = state.tileSamples[static_cast<std::size_t>(tile)];
        if (from >= upTo) return;
        TraceStats stats;
        PathScratch& scratch = scratches.local();
        int x0, y0, x1, y1;
        tileRect(tile, settings.width, settings.height, x0, y0, x1, y1);
        const auto pixels = static_cast<std::uint64_t>(x1 - x0) * static_cast<std::uint64_t>(y1 - y0);
        CameraPackets packets(tracer, *sampler, cameraRays, state, stats, scratch);
        // One sample index of the tile's pixels at a time, a batch of its own (CameraPackets: the same in any pass).
        for (std::uint32_t i = from; i < upTo; ++i) {
            forEachTilePixel(tile, settings.width, settings.height, [&](int x, int y, std::size_t pixel) { packets.add(x, y, pixel, i); });
            packets.flush();
            if (scratch.splitRecords.size() >= kRecordsPerFlush) learn(scratch.splitRecords);
            if (progress) progress->fetch_add(pixels, std::memory_order_relaxed);
        }
        learn(scratch.splitRecords);
        state.tileSamples[static_cast<std::size_t>(tile)] = upTo;
        {
            std::lock_guard<std::mutex> lock(statsMutex);
            state.rays += stats.rays;
            state.badSamples += stats.badSamples;
            const std::uint64_t cameraSamples = pixels * (upTo - from);
            state.samples += cameraSamples;
            state.paths += cameraSamples + stats.extraPaths;
        }
        if (settings.onTileDone) settings.onTileDone();
    };
    forEachTile(settings, renderTile);
}

/// probeLearning with a tracer from makeTracer (switched to recording); its time counts in the state's.
void probeWith(PathTracer& tracer, const Estimator& estimator, const RenderSettings& settings, RenderState& state);

}  // namespace

void renderSegment(const Scene& scene, const Accel& accel, const Estimator& estimator, const RenderSettings& settings, RenderState& state,
                   std::uint32_t upTo, std::atomic<std::uint64_t>* progress) {
    traceSegment(*makeTracer(scene, accel, estimator, settings, state), estimator, settings, state, upTo, progress);
}

void startLearning(const Scene& scene, RenderState& state) {
    if (state.ears) return;
    Vec3 lo, hi;
    scene.bounds(lo, hi);
    state.ears.emplace(ears::Grid(lo, hi));
}

namespace {

/// Whether the render's probe is still to run (probeLearning).
bool probeDue(const RenderSettings& settings, const RenderState& state) {
    return learnsFactors(settings.trace.splitting) && state.sppBound >= ears::kProbeMinSpp && state.ears && !state.ears->probed &&
           state.ears->epoch == 0 && state.samplesReached() == 0;
}

}  // namespace

void probeLearning(const Scene& scene, const Accel& accel, const Estimator& estimator, const RenderSettings& settings, RenderState& state) {
    if (!learnsFactors(settings.trace.splitting) || state.sppBound < ears::kProbeMinSpp) return;
    startLearning(scene, state);
    if (probeDue(settings, state)) probeWith(*makeTracer(scene, accel, estimator, settings, state), estimator, settings, state);
}

namespace {

void probeWith(PathTracer& tracer, const Estimator& estimator, const RenderSettings& settings, RenderState& state) {
    const CostClock clock(state);
    // The first hit's records alone: Learning::learnFromProbe keeps no deeper factor (the same factors as
    // with the deeper vertices recorded, bit for bit; they cost the probe a record each).
    tracer.setRecords(false, true);
    ears::Learning& learning = *state.ears;
    const Scene& scene = tracer.scene();
    const auto sampler =
        makeSampler(effectiveSampler(estimator, settings.sampler), ears::kProbeSamples, mixSeed(settings.seed, ears::kProbeSeed));
    const CameraRays cameraRays(scene.camera, settings.width, settings.height);
    const int tiles = tileCount(settings.width, settings.height);
    // Per tile: its probed pixels' summed variance (added in tile order afterwards: the same double at any
    // thread count), pixels, rays and paths.
    std::vector<double> variance(static_cast<std::size_t>(tiles), 0.0);
    std::vector<std::uint64_t> pixels(static_cast<std::size_t>(tiles), 0), rays(pixels), paths(pixels);
    std::mutex learnMutex;
    RenderSettings all = settings;
    all.tiles = nullptr;  // every tile, on this process's threads
    const auto cancelled = [&] { return settings.cancel && settings.cancel->load(std::memory_order_relaxed); };
    tbb::enumerable_thread_specific<PathScratch> scratches;  // one a thread, as traceSegment's
    forEachTile(all, [&](int tile) {
        if (cancelled()) return;
        TraceStats stats;
        PathScratch& scratch = scratches.local();
        const auto t = static_cast<std::size_t>(tile);
        forEachTilePixel(tile, settings.width, settings.height, [&](int x, int y, std::size_t pixel) {
            if (x % 2 != 0 || y % 2 != 0) return;
            double sum = 0, squares = 0;
            for (std::uint32_t i = 0; i < ears::kProbeSamples; ++i) {
                // Its bad samples count as black and stay out of the render's count (stats are the probe's own).
                const double value = luminance(traceCameraSample(tracer, *sampler, cameraRays, x, y, pixel, i, stats, scratch));
                sum += value, squares += value * value;
            }
            const double n = ears::kProbeSamples;
            variance[t] += std::max(0.0, squares - sum * sum / n) / (n - 1);
            ++pixels[t];
        });
        rays[t] = stats.rays, paths[t] = pixels[t] * ears::kProbeSamples + stats.extraPaths;
        std::lock_guard<std::mutex> lock(learnMutex);
        learning.add(scratch.splitRecords);
        scratch.splitRecords.clear();
    });
    if (cancelled()) {
        // Stopped part way: nothing learned (a resumed render probes again, the same way).
        learning.clearSums();
        return;
    }
    double v = 0;
    std::uint64_t probed = 0, probeRays = 0, probePaths = 0;
    for (std::size_t t = 0; t < variance.size(); ++t) v += variance[t], probed += pixels[t], probeRays += rays[t], probePaths += paths[t];
    learning.learnFromProbe(probed ? v / static_cast<double>(probed) : 0.0, probeRays, probed * ears::kProbeSamples);
    state.rays += probeRays, state.paths += probePaths;
    learning.raysAtStart = state.rays;
    learning.pathsAtStart = state.paths;
}

}  // namespace

bool earsMayRest(const Estimator& estimator, const RenderSettings& settings) {
    return traceSettings(estimator, settings).earsRouletteFloor;
}

bool endEpochIfDone(RenderState& state, bool mayRest) {
    // The render's last epoch (it reaches the spp) has no successor to learn for; a resting EARS learns no more.
    if (!state.ears || state.earsResting() || ears::lastEpoch(state.ears->epoch, state.sppBound) ||
        state.samplesReached() < ears::epochEnd(ears::epochStart(state.ears->epoch)))
        return false;
    // Learning is part of the render's cost: its time counts (the study's CPU-time cost reads it).
    const CostClock clock(state);
    state.ears->advance(state.variancePerSample(), state.rays, state.samples, state.paths, mayRest);
    return true;
}

std::unique_ptr<PathTracer> makeTracer(const Scene& scene, const Accel& accel, const Estimator& estimator, const RenderSettings& settings,
                                       RenderState& state) {
    const CostClock clock(state);
    const bool learns = learnsFactors(settings.trace.splitting);
    if (learns) startLearning(scene, state);
    return std::make_unique<PathTracer>(scene, accel, estimator, traceSettings(estimator, settings), learns ? &*state.ears : nullptr,
                                        recordsEpoch(state));
}

void renderSamples(PathTracer& tracer, const Estimator& estimator, const RenderSettings& settings, RenderState& state, std::uint32_t upTo,
                   std::atomic<std::uint64_t>* progress) {
    if (!learnsFactors(settings.trace.splitting) || settings.tiles) return traceSegment(tracer, estimator, settings, state, upTo, progress);
    // Epoch by epoch: every tile finishes one before the factors of the next are learned, all with the one
    // tracer (making one goes over every triangle: 0.2 s on a 2M-triangle mesh, which a tracer per epoch
    // paid seven times a render).
    upTo = std::min(upTo, state.sppBound);
    if (upTo <= state.samplesReached()) return;
    if (probeDue(settings, state)) probeWith(tracer, estimator, settings, state);
    for (std::uint32_t reached = state.samplesReached(); reached < upTo; reached = state.samplesReached()) {
        // A resting EARS learns nothing more: the rest of the render is one segment (no wait for the last tile
        // at each epoch's end).
        traceSegment(tracer, estimator, settings, state, state.earsResting() ? upTo : std::min(upTo, ears::epochEnd(reached)), progress);
        endEpochIfDone(state, earsMayRest(estimator, settings));
        if (settings.cancel && settings.cancel->load()) return;
    }
}

void renderSamples(const Scene& scene, const Accel& accel, const Estimator& estimator, const RenderSettings& settings, RenderState& state,
                   std::uint32_t upTo, std::atomic<std::uint64_t>* progress) {
    if (std::min(upTo, state.sppBound) <= state.samplesReached()) return;
    const std::unique_ptr<PathTracer> tracer = makeTracer(scene, accel, estimator, settings, state);
    renderSamples(*tracer, estimator, settings, state, upTo, progress);
}

RenderResult resultOf(const RenderState& state, const std::string& sampler) {
    RenderResult result;
    result.image = state.image();
    result.variance = state.variance();
    result.stats.seconds = state.seconds;
    result.stats.rays = state.rays;
    result.stats.samples = state.samples;
    result.stats.paths = state.paths;
    result.stats.cpuSeconds = state.cpuSeconds;
    result.stats.badSamples = state.badSamples;
    result.sampler = sampler;
    return result;
}

RenderResult render(const Scene& scene, const Accel& accel, const Estimator& estimator, const RenderSettings& settings,
                    std::atomic<std::uint64_t>* progress) {
    RenderState state(settings.width, settings.height, settings.spp);
    renderSamples(scene, accel, estimator, settings, state, settings.spp, progress);
    RenderResult result = resultOf(state, effectiveSampler(estimator, settings.sampler));
    result.cancelled = settings.cancel && settings.cancel->load();
    return result;
}

std::string tbbVersion() { return fmt::format("{} (run time {})", TBB_VERSION_STRING, TBB_runtime_version()); }

}  // namespace symphong
