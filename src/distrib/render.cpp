#include "distrib/render.h"

#include "splitting/learning.h"

#include <mpi.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace symphong {

namespace {

constexpr int kTagRequest = 101;     ///< rank -> 0: "give me tiles" (payload: how many it can use)
constexpr int kTagGrant = 102;       ///< 0 -> rank: {first tile, count}; count 0: no more tiles
constexpr int kTagTiles = 103;       ///< rank -> 0: the numbers of the tiles it rendered
constexpr int kTagPixels = 104;      ///< rank -> 0: their state (packTiles), after their sample counts
constexpr int kTagGrantState = 105;  ///< 0 -> rank: the granted tiles' state (packTiles), after the grant
constexpr int kTagLearning = 106;    ///< rank -> 0: --splitting ears: its sums of the epoch's records (ears::CellSums)

/// Doubles a pixel takes in a message: its sum, sum of squares (3 each) and sum of squared luminance.
constexpr std::size_t kPixelDoubles = 7;

/// The state of `tiles` as one message: their sample counts (as doubles, exact below 2^53), then, for
/// each tile with samples, its pixels' sums row by row. Tiles without samples send no pixels.
std::vector<double> packTiles(const RenderState& s, const int* tiles, int count) {
    std::vector<double> out;
    for (int i = 0; i < count; ++i) out.push_back(s.tileSamples[static_cast<std::size_t>(tiles[i])]);
    for (int i = 0; i < count; ++i) {
        if (s.tileSamples[static_cast<std::size_t>(tiles[i])] == 0) continue;
        forEachTilePixel(tiles[i], s.width, s.height, [&](int, int, std::size_t p) {
            out.insert(out.end(), {s.sum[p].x, s.sum[p].y, s.sum[p].z, s.sumSq[p].x, s.sumSq[p].y, s.sumSq[p].z, s.sumLuminanceSq[p]});
        });
    }
    return out;
}

/// The inverse of packTiles: the tiles' counts and sums into `s` (pixels of tiles without samples zeroed).
void unpackTiles(RenderState& s, const int* tiles, int count, const std::vector<double>& in) {
    std::size_t k = static_cast<std::size_t>(count);
    for (int i = 0; i < count; ++i) {
        const auto n = static_cast<std::uint32_t>(in[static_cast<std::size_t>(i)]);
        s.tileSamples[static_cast<std::size_t>(tiles[i])] = n;
        forEachTilePixel(tiles[i], s.width, s.height, [&](int, int, std::size_t p) {
            if (n == 0) {
                s.sum[p] = s.sumSq[p] = Color(0.0), s.sumLuminanceSq[p] = 0;
                return;
            }
            s.sum[p] = Color(in[k], in[k + 1], in[k + 2]), s.sumSq[p] = Color(in[k + 3], in[k + 4], in[k + 5]);
            s.sumLuminanceSq[p] = in[k + 6];
            k += kPixelDoubles;
        });
    }
}

/// A message of T (MPI type `type`: T's own, or MPI_BYTE for a struct sent as its bytes) from `from` with
/// `tag`, whatever its length.
template <class T>
std::vector<T> receiveAll(int from, int tag, MPI_Datatype type) {
    MPI_Status status;
    MPI_Probe(from, tag, MPI_COMM_WORLD, &status);
    int n = 0, size = 0;
    MPI_Get_count(&status, type, &n);
    MPI_Type_size(type, &size);
    std::vector<T> data(static_cast<std::size_t>(n) * static_cast<std::size_t>(size) / sizeof(T));
    MPI_Recv(data.data(), n, type, from, tag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    return data;
}

std::vector<double> receiveDoubles(int from, int tag) { return receiveAll<double>(from, tag, MPI_DOUBLE); }

/// Rank 0's shared counter: its own threads draw from it directly, the dispatcher for the others.
class CounterSource : public TileSource {
public:
    CounterSource(int total, const std::atomic<bool>* cancel) : total_(total), cancel_(cancel) {}
    bool next(int& tile) override {
        if (cancel_ && cancel_->load(std::memory_order_relaxed)) return false;
        const int t = next_.fetch_add(1, std::memory_order_relaxed);
        if (t >= total_) return false;
        tile = t;
        return true;
    }
    int remaining() const { return std::max(0, total_ - next_.load(std::memory_order_relaxed)); }
    /// Up to `want` consecutive tiles; count 0 when none are left (or the render is cancelled).
    void take(int want, int& first, int& count) {
        first = 0, count = 0;
        if (cancel_ && cancel_->load(std::memory_order_relaxed)) return;
        const int start = next_.fetch_add(want, std::memory_order_relaxed);
        if (start >= total_) return;
        first = start, count = std::min(want, total_ - start);
    }

private:
    const int total_;
    const std::atomic<bool>* cancel_;
    std::atomic<int> next_{0};
};

/// The other ranks' source: asks rank 0 for two tiles per thread at a time (with their state so far,
/// unpacked into this rank's state), hands them out one by one, and records which tiles it rendered.
class RemoteSource : public TileSource {
public:
    RemoteSource(int threads, RenderState& state) : want_(2 * std::max(1, threads)), state_(state) {}
    bool next(int& tile) override {
        std::lock_guard lock(mutex_);
        if (cursor_ == end_) {
            if (dry_) return false;
            int grant[2] = {0, 0};
            MPI_Send(&want_, 1, MPI_INT, 0, kTagRequest, MPI_COMM_WORLD);
            MPI_Recv(grant, 2, MPI_INT, 0, kTagGrant, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
            if (grant[1] == 0) {
                dry_ = true;
                return false;
            }
            std::vector<int> tiles(static_cast<std::size_t>(grant[1]));
            for (int i = 0; i < grant[1]; ++i) tiles[static_cast<std::size_t>(i)] = grant[0] + i;
            unpackTiles(state_, tiles.data(), grant[1], receiveDoubles(0, kTagGrantState));
            cursor_ = grant[0], end_ = grant[0] + grant[1];
        }
        tile = cursor_++;
        rendered_.push_back(tile);
        return true;
    }
    const std::vector<int>& rendered() const { return rendered_; }

private:
    int want_;
    RenderState& state_;
    std::mutex mutex_;
    int cursor_ = 0, end_ = 0;
    bool dry_ = false;
    std::vector<int> rendered_;
};

/// The samples tile `tile` takes to reach `upTo`.
std::uint64_t tileWork(int tile, const RenderState& s, std::uint32_t upTo) {
    int x0, y0, x1, y1;
    tileRect(tile, s.width, s.height, x0, y0, x1, y1);
    const std::uint32_t has = std::min(upTo, s.tileSamples[static_cast<std::size_t>(tile)]);
    return static_cast<std::uint64_t>(x1 - x0) * static_cast<std::uint64_t>(y1 - y0) * (upTo - has);
}

/// Rank 0's dispatcher: answers the other ranks' requests for tiles until every one of them has been told
/// that none are left, counting the samples of finished grants into `progress`.
void dispatchTiles(const MpiJob& job, CounterSource& counter, const RenderState& state, std::uint32_t upTo,
                   std::atomic<std::uint64_t>* progress) {
    std::vector<std::uint64_t> pending(static_cast<std::size_t>(job.size()), 0);  // samples granted, not yet known done
    int open = job.size() - 1;
    while (open > 0) {
        // Polled, not a blocking receive: Open MPI spins in a blocking call and would take a core from this
        // rank's render threads. 0.5 ms between polls: against 10 ms or more of work per grant (at least
        // two 16x16 tiles), a wait of at most 5%, and only at the end of a render.
        int waiting = 0;
        MPI_Status status;
        MPI_Iprobe(MPI_ANY_SOURCE, kTagRequest, MPI_COMM_WORLD, &waiting, &status);
        if (!waiting) {
            std::this_thread::sleep_for(std::chrono::microseconds(500));
            continue;
        }
        int want = 0;
        MPI_Recv(&want, 1, MPI_INT, status.MPI_SOURCE, kTagRequest, MPI_COMM_WORLD, &status);
        const int from = status.MPI_SOURCE;
        // A request means the rank finished what it was given before.
        if (progress) progress->fetch_add(pending[static_cast<std::size_t>(from)], std::memory_order_relaxed);
        pending[static_cast<std::size_t>(from)] = 0;
        // Guided self-scheduling: a share of what is left (large grants early, one request per several
        // hundred milliseconds), shrinking to what the rank asked for near the end, so that a slow rank
        // holds no one back at the finish.
        int grant[2];
        counter.take(std::max({1, want, counter.remaining() / (2 * job.size())}), grant[0], grant[1]);
        for (int t = grant[0]; t < grant[0] + grant[1]; ++t) pending[static_cast<std::size_t>(from)] += tileWork(t, state, upTo);
        MPI_Send(grant, 2, MPI_INT, from, kTagGrant, MPI_COMM_WORLD);
        if (grant[1] == 0) {
            --open;
            continue;
        }
        // The granted tiles' state: rank 0's threads never take these tiles, so reading it here is safe.
        std::vector<int> tiles(static_cast<std::size_t>(grant[1]));
        for (int i = 0; i < grant[1]; ++i) tiles[static_cast<std::size_t>(i)] = grant[0] + i;
        const std::vector<double> packed = packTiles(state, tiles.data(), grant[1]);
        MPI_Send(packed.data(), static_cast<int>(packed.size()), MPI_DOUBLE, from, kTagGrantState, MPI_COMM_WORLD);
    }
}

/// Another rank's tiles to rank 0: their numbers, then their state (packTiles).
void sendTiles(const std::vector<int>& tiles, const RenderState& state) {
    const std::vector<double> packed = packTiles(state, tiles.data(), static_cast<int>(tiles.size()));
    MPI_Send(tiles.data(), static_cast<int>(tiles.size()), MPI_INT, 0, kTagTiles, MPI_COMM_WORLD);
    MPI_Send(packed.data(), static_cast<int>(packed.size()), MPI_DOUBLE, 0, kTagPixels, MPI_COMM_WORLD);
}

/// On rank 0: every other rank's tiles into the state; the number of tiles each rendered.
void gatherTiles(const MpiJob& job, RenderState& state, std::vector<int>& tilesPerRank) {
    for (int r = 1; r < job.size(); ++r) {
        const std::vector<int> tiles = receiveAll<int>(r, kTagTiles, MPI_INT);
        const int n = static_cast<int>(tiles.size());
        unpackTiles(state, tiles.data(), n, receiveDoubles(r, kTagPixels));
        tilesPerRank[static_cast<std::size_t>(r)] = n;
    }
}

/// --splitting ears: what a rank needs of rank 0's learning to render an epoch (its grid's box, the epoch
/// and its factors) sent to every rank, whose own sums start empty. Rank 0's learning is the render's:
/// it may come from a checkpoint.
void shareLearning(const MpiJob& job, const Scene& scene, RenderState& state) {
    startLearning(scene, state);
    ears::Learning& l = *state.ears;
    double box[7] = {l.grid.lo().x, l.grid.lo().y, l.grid.lo().z, l.grid.hi().x, l.grid.hi().y, l.grid.hi().z, l.factors.scale};
    // The epoch, whether there are factors, and whether rank 0 probed: after a probe no rank records the first
    // hit from epoch 1 on (render/renderer.cpp recordsFirstHit), as one process would not.
    // And whether EARS rests (every rank then traces as --splitting none).
    std::int32_t epochAndFactors[4] = {l.epoch, l.factors.empty() ? 0 : 1, l.probed ? 1 : 0, l.resting ? 1 : 0};
    MPI_Bcast(box, 7, MPI_DOUBLE, 0, MPI_COMM_WORLD);
    MPI_Bcast(epochAndFactors, 4, MPI_INT32_T, 0, MPI_COMM_WORLD);
    const int cells = static_cast<int>(ears::Grid::cellCount());
    if (!job.root()) {
        l.grid = ears::Grid::fromBox(Vec3(box[0], box[1], box[2]), Vec3(box[3], box[4], box[5]));
        l.epoch = epochAndFactors[0];
        l.probed = epochAndFactors[2] != 0;
        l.resting = epochAndFactors[3] != 0;
        l.factors = ears::Factors{};
        l.factors.scale = box[6];
        if (epochAndFactors[1])
            for (std::vector<float>* table : l.factors.tables()) table->resize(static_cast<std::size_t>(cells));
        l.clearSums();
    }
    if (epochAndFactors[1])
        for (std::vector<float>* table : l.factors.tables()) MPI_Bcast(table->data(), cells, MPI_FLOAT, 0, MPI_COMM_WORLD);
}

/// One slot of a rank's sums as gatherLearning sends it: its index and its sums.
struct SlotSums {
    std::uint64_t slot;
    ears::CellSums sums;
};

/// --splitting ears: every rank's sums of the epoch's records added into rank 0's (exact integers: the
/// same in any order, so the same as one process's). A rank sends only the slots its records reached
/// (Learning::occupied: the Cornell box's about a fifth of the finest cells), not the whole 7.2 MB table.
void gatherLearning(const MpiJob& job, RenderState& state) {
    const ears::SumTable& sums = state.ears->sums();
    if (!job.root()) {
        std::vector<SlotSums> mine;
        state.ears->occupied().forEach(0, sums.size(), [&](std::size_t slot) {
            if (!sums[slot].empty()) mine.push_back({slot, sums[slot]});
        });
        MPI_Send(mine.data(), static_cast<int>(mine.size() * sizeof(SlotSums)), MPI_BYTE, 0, kTagLearning, MPI_COMM_WORLD);
        return;
    }
    for (int r = 1; r < job.size(); ++r) {
        for (const SlotSums& s : receiveAll<SlotSums>(r, kTagLearning, MPI_BYTE)) {
            if (s.slot >= sums.size())
                throw std::runtime_error("rank " + std::to_string(r) + " sent EARS sums for slot " + std::to_string(s.slot) + " of " +
                                         std::to_string(sums.size()));
            state.ears->add(static_cast<std::size_t>(s.slot), s.sums);
        }
    }
}

void renderSegmentDistributed(const MpiJob& job, const Scene& scene, const Accel& accel, const Estimator& estimator,
                              const RenderSettings& settings, RenderState& state, std::uint32_t upTo, std::atomic<std::uint64_t>* progress,
                              DistributedStats* distributed, std::unique_ptr<PathTracer>& tracer) {
    const auto start = std::chrono::steady_clock::now();
    const int total = tileCount(settings.width, settings.height);
    const int threads = settings.threads > 0 ? settings.threads : static_cast<int>(std::thread::hardware_concurrency());
    const double secondsBefore = state.seconds;
    const std::uint64_t before[4] = {state.rays, state.badSamples, state.samples, state.paths};
    const double cpuBefore = state.cpuSeconds;
    RenderSettings local = settings;
    // Only rank 0 acts on a cancellation (it stops handing out tiles); a rank that skipped its tiles on its
    // own would leave holes that rank 0 does not know about.
    if (!job.root()) local.cancel = nullptr;
    std::vector<int> tilesPerRank(static_cast<std::size_t>(job.size()), 0);
    double gatherSeconds = 0;
    const auto trace = [&](std::atomic<std::uint64_t>* counted) {
        if (!tracer) tracer = makeTracer(scene, accel, estimator, local, state);
        renderSamples(*tracer, estimator, local, state, upTo, counted);
    };
    if (job.root()) {
        CounterSource counter(total, settings.cancel);
        local.tiles = &counter;
        std::thread dispatcher([&] { dispatchTiles(job, counter, state, upTo, progress); });
        trace(progress);
        dispatcher.join();
        const auto gatherStart = std::chrono::steady_clock::now();
        gatherTiles(job, state, tilesPerRank);
        gatherSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - gatherStart).count();
    } else {
        RemoteSource remote(threads, state);
        local.tiles = &remote;
        // Every worker loop ends on next() returning false, which only happens once rank 0 has said
        // that no tiles are left: the dispatcher has heard from this rank for the last time.
        trace(nullptr);
        sendTiles(remote.rendered(), state);
    }
    // The whole job's counts on rank 0 (each rank's own additions summed); its time from the start of
    // the pass to the last pixel gathered.
    std::uint64_t mine[4] = {state.rays - before[0], state.badSamples - before[1], state.samples - before[2], state.paths - before[3]},
                  sums[4] = {0, 0, 0, 0};
    MPI_Reduce(mine, sums, 4, MPI_UINT64_T, MPI_SUM, 0, MPI_COMM_WORLD);
    const double myCpu = state.cpuSeconds - cpuBefore;
    double cpuSum = 0;
    MPI_Reduce(&myCpu, &cpuSum, 1, MPI_DOUBLE, MPI_SUM, 0, MPI_COMM_WORLD);
    if (!job.root()) return;
    state.rays = before[0] + sums[0], state.badSamples = before[1] + sums[1], state.samples = before[2] + sums[2];
    state.paths = before[3] + sums[3];
    state.cpuSeconds = cpuBefore + cpuSum;
    state.seconds = secondsBefore + std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (distributed) {
        int own = total;
        for (int r = 1; r < job.size(); ++r) own -= tilesPerRank[static_cast<std::size_t>(r)];
        tilesPerRank[0] = own;
        // Summed over the calls of one render (--splitting ears renders epoch by epoch).
        distributed->gatherSeconds += gatherSeconds;
        distributed->tilesPerRank.resize(tilesPerRank.size(), 0);
        for (std::size_t r = 0; r < tilesPerRank.size(); ++r) distributed->tilesPerRank[r] += tilesPerRank[r];
    }
}

}  // namespace

void renderSamplesDistributed(const MpiJob& job, const Scene& scene, const Accel& accel, const Estimator& estimator,
                              const RenderSettings& settings, RenderState& state, std::uint32_t upTo, std::atomic<std::uint64_t>* progress,
                              DistributedStats* distributed, std::unique_ptr<PathTracer>* kept) {
    std::unique_ptr<PathTracer> own;
    std::unique_ptr<PathTracer>& tracer = kept ? *kept : own;
    if (!job.active() || job.size() == 1) {
        if (std::min(upTo, state.sppBound) <= state.samplesReached()) return;
        if (!tracer) tracer = makeTracer(scene, accel, estimator, settings, state);
        return renderSamples(*tracer, estimator, settings, state, upTo, progress);
    }
    if (!learnsFactors(settings.trace.splitting))
        return renderSegmentDistributed(job, scene, accel, estimator, settings, state, upTo, progress, distributed, tracer);
    // --splitting ears: epoch by epoch, as renderSamples in one process. Rank 0, which holds the state,
    // says where each segment ends (0: no more); before it every rank gets rank 0's factors, after it rank
    // 0 adds every rank's records and learns the next epoch's factors. Rank 0 alone runs the learning
    // pass before the first epoch (it is small and the same at any thread count).
    if (job.root() && std::min(upTo, state.sppBound) > state.samplesReached()) probeLearning(scene, accel, estimator, settings, state);
    for (;;) {
        std::uint32_t end = 0;
        if (job.root()) {
            const std::uint32_t reached = state.samplesReached(), bound = std::min(upTo, state.sppBound);
            if (reached < bound && !(settings.cancel && settings.cancel->load()))
                end = state.earsResting() ? bound : std::min(bound, ears::epochEnd(reached));
        }
        MPI_Bcast(&end, 1, MPI_UINT32_T, 0, MPI_COMM_WORLD);
        if (end == 0) return;
        shareLearning(job, scene, state);
        renderSegmentDistributed(job, scene, accel, estimator, settings, state, end, progress, distributed, tracer);
        gatherLearning(job, state);
        if (job.root()) endEpochIfDone(state, earsMayRest(estimator, settings));
    }
}

PassRunner leadPasses(const MpiJob& job, const Scene& scene, const Accel& accel, const Estimator& estimator, const RenderSettings& settings,
                      std::atomic<std::uint64_t>* progress) {
    // One tracer for every pass of the render (render/renderer.h makeTracer), made at the first; every
    // other rank keeps its own the same way (followPasses).
    auto tracer = std::make_shared<std::unique_ptr<PathTracer>>();
    return [&job, &scene, &accel, &estimator, settings, progress, tracer](RenderState& state, std::uint32_t upTo) {
        if (job.active() && job.size() > 1) {
            std::uint32_t pass = upTo;
            MPI_Bcast(&pass, 1, MPI_UINT32_T, 0, MPI_COMM_WORLD);
        }
        renderSamplesDistributed(job, scene, accel, estimator, settings, state, upTo, progress, nullptr, tracer.get());
    };
}

void endPasses(const MpiJob& job) {
    if (!job.active() || job.size() == 1) return;
    std::uint32_t none = 0;
    MPI_Bcast(&none, 1, MPI_UINT32_T, 0, MPI_COMM_WORLD);
}

void followPasses(const MpiJob& job, const Scene& scene, const Accel& accel, const Estimator& estimator, const RenderSettings& settings) {
    RenderState scratch(settings.width, settings.height, settings.spp);
    std::unique_ptr<PathTracer> tracer;  // for every pass, as rank 0's (leadPasses)
    for (;;) {
        std::uint32_t upTo = 0;
        MPI_Bcast(&upTo, 1, MPI_UINT32_T, 0, MPI_COMM_WORLD);
        if (upTo == 0) return;
        renderSamplesDistributed(job, scene, accel, estimator, settings, scratch, upTo, nullptr, nullptr, &tracer);
    }
}

RenderResult renderDistributed(const MpiJob& job, const Scene& scene, const Accel& accel, const Estimator& estimator,
                               const RenderSettings& settings, std::atomic<std::uint64_t>* progress, DistributedStats* distributed) {
    if (!job.active() || job.size() == 1) return render(scene, accel, estimator, settings, progress);
    RenderState state(settings.width, settings.height, settings.spp);
    renderSamplesDistributed(job, scene, accel, estimator, settings, state, settings.spp, progress, distributed);
    RenderResult result = resultOf(state, effectiveSampler(estimator, settings.sampler));
    // A cancelled rank 0 marks every rank's result cancelled.
    int cancelled = settings.cancel && settings.cancel->load() ? 1 : 0;
    MPI_Bcast(&cancelled, 1, MPI_INT, 0, MPI_COMM_WORLD);
    result.cancelled = cancelled != 0;
    return result;
}

}  // namespace symphong
