#include "distrib/render.h"

#include <mpi.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <thread>
#include <vector>

namespace symphong {

namespace {

constexpr int kTagRequest = 101;  ///< rank -> 0: "give me tiles" (payload: how many it can use)
constexpr int kTagGrant = 102;    ///< 0 -> rank: {first tile, count}; count 0: no more tiles
constexpr int kTagTiles = 103;    ///< rank -> 0: the numbers of the tiles it rendered
constexpr int kTagPixels = 104;   ///< rank -> 0: their pixels, image then variance, tile by tile

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

/// The other ranks' source: asks rank 0 for two tiles per thread at a time, hands them out one by one,
/// and records which tiles it rendered.
class RemoteSource : public TileSource {
public:
    explicit RemoteSource(int threads) : want_(2 * std::max(1, threads)) {}
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
            cursor_ = grant[0], end_ = grant[0] + grant[1];
        }
        tile = cursor_++;
        rendered_.push_back(tile);
        return true;
    }
    const std::vector<int>& rendered() const { return rendered_; }

private:
    int want_;
    std::mutex mutex_;
    int cursor_ = 0, end_ = 0;
    bool dry_ = false;
    std::vector<int> rendered_;
};

std::uint64_t tileSamples(int tile, const RenderSettings& s) {
    int x0, y0, x1, y1;
    tileRect(tile, s.width, s.height, x0, y0, x1, y1);
    return static_cast<std::uint64_t>(x1 - x0) * (y1 - y0) * s.spp;
}

/// Rank 0's dispatcher: answers the other ranks' requests for tiles until every one of them has been told
/// that none are left, counting the samples of finished grants into `progress`.
void dispatchTiles(const MpiJob& job, CounterSource& counter, const RenderSettings& settings, std::atomic<std::uint64_t>* progress) {
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
        for (int t = grant[0]; t < grant[0] + grant[1]; ++t) pending[static_cast<std::size_t>(from)] += tileSamples(t, settings);
        MPI_Send(grant, 2, MPI_INT, from, kTagGrant, MPI_COMM_WORLD);
        if (grant[1] == 0) --open;
    }
}

/// Another rank's tiles to rank 0: their numbers, then image and variance pixels as doubles.
void sendTiles(const std::vector<int>& tiles, const RenderResult& result, const RenderSettings& settings) {
    std::vector<double> pixels;
    for (int tile : tiles) {
        int x0, y0, x1, y1;
        tileRect(tile, settings.width, settings.height, x0, y0, x1, y1);
        for (const Image* img : {&result.image, &result.variance})
            for (int y = y0; y < y1; ++y)
                for (int x = x0; x < x1; ++x)
                    for (int c = 0; c < 3; ++c) pixels.push_back(img->at(x, y)[c]);
    }
    MPI_Send(tiles.data(), static_cast<int>(tiles.size()), MPI_INT, 0, kTagTiles, MPI_COMM_WORLD);
    MPI_Send(pixels.data(), static_cast<int>(pixels.size()), MPI_DOUBLE, 0, kTagPixels, MPI_COMM_WORLD);
}

/// On rank 0: every other rank's tiles into the result; the number of tiles each rendered.
void gatherTiles(const MpiJob& job, RenderResult& result, const RenderSettings& settings, std::vector<int>& tilesPerRank) {
    for (int r = 1; r < job.size(); ++r) {
        MPI_Status status;
        MPI_Probe(r, kTagTiles, MPI_COMM_WORLD, &status);
        int n = 0;
        MPI_Get_count(&status, MPI_INT, &n);
        std::vector<int> tiles(static_cast<std::size_t>(n));
        MPI_Recv(tiles.data(), n, MPI_INT, r, kTagTiles, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        MPI_Probe(r, kTagPixels, MPI_COMM_WORLD, &status);
        int m = 0;
        MPI_Get_count(&status, MPI_DOUBLE, &m);
        std::vector<double> pixels(static_cast<std::size_t>(m));
        MPI_Recv(pixels.data(), m, MPI_DOUBLE, r, kTagPixels, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        std::size_t k = 0;
        for (int tile : tiles) {
            int x0, y0, x1, y1;
            tileRect(tile, settings.width, settings.height, x0, y0, x1, y1);
            for (Image* img : {&result.image, &result.variance})
                for (int y = y0; y < y1; ++y)
                    for (int x = x0; x < x1; ++x)
                        for (int c = 0; c < 3; ++c) img->at(x, y)[c] = pixels[k++];
        }
        tilesPerRank[static_cast<std::size_t>(r)] = n;
    }
}

}  // namespace

RenderResult renderDistributed(const MpiJob& job, const Scene& scene, const Accel& accel, const Estimator& estimator,
                               const RenderSettings& settings, std::atomic<std::uint64_t>* progress, DistributedStats* distributed) {
    if (!job.active() || job.size() == 1) return render(scene, accel, estimator, settings, progress);
    const auto start = std::chrono::steady_clock::now();
    const int total = tileCount(settings.width, settings.height);
    const int threads = settings.threads > 0 ? settings.threads : static_cast<int>(std::thread::hardware_concurrency());
    RenderResult result;
    RenderSettings local = settings;
    // Only rank 0 acts on a cancellation (it stops handing out tiles); a rank that skipped its tiles on its
    // own would leave holes in an image that is not marked cancelled.
    if (!job.root()) local.cancel = nullptr;
    std::vector<int> tilesPerRank(static_cast<std::size_t>(job.size()), 0);
    double gatherSeconds = 0;
    if (job.root()) {
        CounterSource counter(total, settings.cancel);
        local.tiles = &counter;
        std::thread dispatcher([&] { dispatchTiles(job, counter, settings, progress); });
        result = render(scene, accel, estimator, local, progress);
        dispatcher.join();
        const auto gatherStart = std::chrono::steady_clock::now();
        gatherTiles(job, result, settings, tilesPerRank);
        gatherSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - gatherStart).count();
    } else {
        RemoteSource remote(threads);
        local.tiles = &remote;
        // Every worker loop ends on next() returning false, which only happens once rank 0 has said
        // that no tiles are left: the dispatcher has heard from this rank for the last time.
        result = render(scene, accel, estimator, local, nullptr);
        sendTiles(remote.rendered(), result, settings);
    }

    // The whole job's counts on rank 0; a cancelled rank 0 marks every rank's result cancelled.
    std::uint64_t mine[2] = {result.stats.rays, result.stats.badSamples}, sums[2] = {0, 0};
    MPI_Reduce(mine, sums, 2, MPI_UINT64_T, MPI_SUM, 0, MPI_COMM_WORLD);
    int cancelled = result.cancelled ? 1 : 0;
    MPI_Bcast(&cancelled, 1, MPI_INT, 0, MPI_COMM_WORLD);
    result.cancelled = cancelled != 0;
    if (job.root()) {
        result.stats.rays = sums[0], result.stats.badSamples = sums[1];
        result.stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        if (distributed) {
            int own = total;
            for (int r = 1; r < job.size(); ++r) own -= tilesPerRank[static_cast<std::size_t>(r)];
            tilesPerRank[0] = own;
            distributed->gatherSeconds = gatherSeconds;
            distributed->tilesPerRank = tilesPerRank;
        }
    }
    return result;
}

}  // namespace symphong
