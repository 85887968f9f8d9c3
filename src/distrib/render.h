// distrib/render.h — one render shared by the ranks of an MPI job. Rank 0 hands out tiles as ranks ask
// for them (a dispatcher thread answers requests from a shared counter that its own threads also draw
// from), so a slow rank takes fewer tiles instead of holding the others back; every rank renders its
// tiles with its oneTBB threads; at the end each rank sends its tiles' pixels to rank 0. A tile's pixels
// depend only on its number (the samplers' per-pixel, per-sample streams), so the image is bit for bit
// the single-process one at any number of ranks and threads.
#pragma once

#include "distrib/mpi_job.h"
#include "render/progressive.h"
#include "render/renderer.h"

namespace symphong {

struct DistributedStats {
    double gatherSeconds = 0;       ///< rank 0: receiving and placing the other ranks' tiles
    std::vector<int> tilesPerRank;  ///< rank 0: how many tiles each rank rendered
};

/// Collective over the job's ranks: takes every tile of `state` to `upTo` samples (renderSamples in a job
/// of one rank). Rank 0 holds the whole state: it hands each granted tile's sums out with the tile, and
/// the rank that renders it sends them back, so a pixel's samples are added in order wherever they are
/// taken and the state is bit for bit the single-process one. On the other ranks `state` is scratch (of
/// the image's size). Rank 0's state gains the whole job's rays, samples, paths and CPU time (summed over the ranks) and
/// the pass's wall time. With --splitting ears it renders epoch by epoch (splitting/learning.h): rank 0
/// sends its learned factors to every rank before an epoch's tiles and adds their records to its sums
/// after them (exact integer sums), so the image is the single-process one too. `tracer`: where this rank
/// keeps its path tracer for `state` from call to call (a render's passes: making one goes over every
/// triangle, render/renderer.h makeTracer); without it, one for the call (every epoch of it).
void renderSamplesDistributed(const MpiJob& job, const Scene& scene, const Accel& accel, const Estimator& estimator,
                              const RenderSettings& settings, RenderState& state, std::uint32_t upTo,
                              std::atomic<std::uint64_t>* progress = nullptr, DistributedStats* distributed = nullptr,
                              std::unique_ptr<PathTracer>* tracer = nullptr);

/// Passes (render/progressive.h) shared by the job: rank 0 renders them with the runner of leadPasses,
/// which first tells the other ranks each pass's sample count, and calls endPasses when they are over;
/// the other ranks call followPasses, which renders every pass with rank 0 until told to stop. The state
/// lives on rank 0 alone, so a job resumed from a checkpoint may have any number of ranks. In one process
/// the runner keeps one tracer (render/renderer.h makeTracer) for every pass: it serves one state.
PassRunner leadPasses(const MpiJob& job, const Scene& scene, const Accel& accel, const Estimator& estimator, const RenderSettings& settings,
                      std::atomic<std::uint64_t>* progress);
void endPasses(const MpiJob& job);
void followPasses(const MpiJob& job, const Scene& scene, const Accel& accel, const Estimator& estimator, const RenderSettings& settings);

/// Collective over the job's ranks (a plain render() in a job of one rank). On rank 0 the result is the
/// whole image, its variance and the whole job's statistics (rays summed over ranks; seconds from the
/// start to the last pixel gathered); on the other ranks it holds only their own tiles. `progress`
/// (rank 0) counts the samples of every rank's finished tiles. Cancelling (settings.cancel) on rank 0
/// stops handing out tiles; the result is then marked cancelled on every rank.
RenderResult renderDistributed(const MpiJob& job, const Scene& scene, const Accel& accel, const Estimator& estimator,
                               const RenderSettings& settings, std::atomic<std::uint64_t>* progress = nullptr,
                               DistributedStats* distributed = nullptr);

}  // namespace symphong
