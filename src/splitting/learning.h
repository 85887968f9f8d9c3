// splitting/learning.h — when and from what a render learns its EARS factors. The samples of a pixel
// come in epochs of doubling size: samples [0, 2) are epoch 0, rendered with the first-hit factors of a
// probe (a small learning pass whose samples are not the image's, below) or, in renders too short for
// one, without learned factors, and samples [2^e, 2^(e+1)) are epoch e, rendered with the factors learned
// from epoch e - 1's continuations (and the image's variance and cost so far). So the factors a sample uses depend only on samples of
// earlier epochs, never on the sample itself (the estimate stays unbiased), and not on how the render
// was cut into passes, threads, ranks or runs: every tile finishes an epoch before any tile starts the
// next, and the sums are exact integers (splitting/ears.h CellSums), the same in any order of adding.
#pragma once

#include "splitting/ears.h"

#include <algorithm>
#include <cstdint>
#include <vector>

namespace symphong::ears {

/// One continuation as the path tracer reports it: its vertex's finest cell (Grid::cell at the finest
/// level, found once for the vertex's factor), what it brought back (the luminance of its estimate,
/// before the vertex's 1/q) and the rays it took; or, in the FirstHitVertex section, one first-hit vertex:
/// its continuations' sample variance and rays = 1 when it had two or more continuations (else 0 and 0).
/// 16 bytes (a render makes one per continuation): the cell and section as one index into Learning::sums,
/// the rays saturated at 2^32 - 1.
struct Record {
    double value = 0;
    std::uint32_t rays = 0;
    std::uint32_t slot = 0;  ///< section x Grid::cellCount() + cell: the record's entry of Learning::sums

    Record() = default;
    Record(std::uint32_t cell, double value, std::uint64_t rays, Section section)
        : value(value),
          rays(static_cast<std::uint32_t>(std::min<std::uint64_t>(rays, 0xffffffffu))),
          slot(static_cast<std::uint32_t>(sectionStart(section) + cell)) {}
};
static_assert(sizeof(Record) == 16);

/// The epoch of sample index i (0 for i < 2, else floor(log2 i)).
int epochOf(std::uint32_t sample);
/// The first sample index of the epoch after the one that sample `reached` is in.
std::uint32_t epochEnd(std::uint32_t reached);
/// The first sample index of epoch e (0, then 2^e).
std::uint32_t epochStart(int epoch);
/// Whether epoch e is the last of a render of `spp` samples (it reaches the spp): no epoch learns from it.
inline bool lastEpoch(int epoch, std::uint32_t spp) { return epochEnd(epochStart(epoch)) >= spp; }

/// The probe: before the image's first sample, kProbeSamples camera samples of a pattern of its own (the
/// render's seed mixed with kProbeSeed) in one pixel of every 2 x 2, traced and recorded like epoch 0 but
/// never added to the image, teach epoch 0 its factors (render/renderer.h probeLearning). The image's
/// samples then split their first hits by one fixed factor per cell from the first sample on: the factors
/// of the first hit are learned from the probe alone and kept for the whole render, since a pixel whose
/// samples took different numbers of first-hit continuations would break the block pattern of those
/// continuations (SampleStream::blockContinuation: a sample with fewer continuations leaves holes in the
/// pixel's net, and an unsplit epoch 0 in the image cost the smooth-sky scene most of its gain). Deeper
/// vertices learn on from epoch to epoch. Renders of fewer than kProbeMinSpp samples a pixel have no probe
/// (it would cost them too large a share): their epoch 0 renders unlearned, every later one as above.
inline constexpr std::uint32_t kProbeSamples = 2;
/// EARS rests (Learning::resting) after an epoch from kRestFromEpoch on whose vertices took fewer than this
/// many continuations beyond one per vertex (the render's extra paths), per camera sample: its learned
/// factors split nothing there, and under a roulette floor (TraceSettings::earsRouletteFloor: roulette
/// never harder than plain) they are then nearly the floor itself, while looking them up and recording
/// every continuation cost the render 8%-11% of its time (the sun and diffuse scenes of the study). A
/// resting render's vertices take the floor (PathTracer::restingFactor) and nothing is looked up, recorded
/// or learned (docs/estimators.md "When EARS rests").
inline constexpr double kRestBelowExtraPaths = 0.01;
/// The first epoch that can decide it: epoch 0's deeper vertices are unlearned. Epoch 1 (factors from epoch
/// 0's 2 spp) separates the scenes as cleanly as later epochs do (docs/performance.md "EARS rests after epoch
/// 1"), and deciding there keeps 4 more samples of 64 off the learning path.
inline constexpr int kRestFromEpoch = 1;
/// Learning::pathsAtStart of a checkpoint written before it was kept: that epoch cannot decide to rest.
inline constexpr std::uint64_t kUnknownPaths = ~std::uint64_t{0};
inline constexpr std::uint32_t kProbeMinSpp = 8;
inline constexpr std::uint64_t kProbeSeed = 0x70726f6265ull;

struct Learning {
    Grid grid;
    bool probed = false;             ///< the probe ran: its first-hit factors hold for the whole render
    int epoch = 0;                   ///< the epoch being rendered
    Factors factors;                 ///< its factors (none in epoch 0, or when the image had no variance)
    std::uint64_t raysAtStart = 0;   ///< the render's rays when the epoch began
    std::uint64_t samplesAtStart = 0;  ///< and its camera samples
    std::uint64_t pathsAtStart = 0;    ///< and its paths (kUnknownPaths: not known)
    /// EARS rests for the rest of the render (kRestBelowExtraPaths): its vertices take one continuation and
    /// roulette by throughput, no factor is looked up, nothing is recorded and nothing learned.
    bool resting = false;
    double varianceAtStart = 0;      ///< and the image's variance per camera sample over all samples before it

    Learning() = default;
    explicit Learning(const Grid& g) : grid(g), sums_(sumCount()), occupied_(sumCount()) {}
    static std::size_t sumCount() { return kSections * Grid::cellCount(); }

    /// The epoch's records so far, per section (ears.h Section) and cell of every level.
    const SumTable& sums() const { return sums_; }
    /// The slots of sums() that hold records (a superset of the non-empty ones).
    const CellSet& occupied() const { return occupied_; }
    /// Empties the sums (all sumCount() cells).
    void clearSums();
    /// Adds sums to one slot (section x Grid::cellCount() + cell): a checkpoint's, read back.
    void add(std::size_t slot, const CellSums& s);

    /// Adds a record to its section's finest cell (the coarser ones get their sums when the epoch ends).
    void add(const Record& r);
    /// Adds records in order, their cells fetched into the cache a few records ahead (cells are scattered
    /// over megabytes: one add at a time would wait on memory for each).
    void add(const std::vector<Record>& records);
    /// Ends the epoch: the next one's factors from this one's sums (after a probe, the first hit's: the
    /// lesser of the probe's and epoch 0's at the end of epoch 0, then those for good; its MIS shares
    /// epoch 0's, then those for good), its cost per camera sample (from the
    /// render's rays and samples now) and its variance per camera sample, from the image's over all
    /// samples now (`variancePerSample`) and at the epoch's start: an epoch after the first has as many
    /// samples as all before it, so its variance is about 2 V_now - V_start.
    /// `paths` (the render's paths now) and `mayRest` (its roulette is floored at plain roulette's) decide
    /// whether EARS rests from now on (kRestBelowExtraPaths); an epoch that decides it learns nothing (its
    /// factors stay the ones it rendered with, its sums are emptied).
    void advance(double variancePerSample, std::uint64_t rays, std::uint64_t samples, std::uint64_t paths = kUnknownPaths,
                 bool mayRest = false);
    /// Ends the probe: epoch 0's first-hit factors from its sums, `rays` over its `samples` camera samples
    /// and the variance per camera sample of its pixels (deeper vertices stay unlearned); the sums start
    /// empty for epoch 0, the epoch stays 0.
    void learnFromProbe(double variancePerSample, std::uint64_t rays, std::uint64_t samples);

    /// The bytes the structure holds: the sums, the occupied set and the two sets of factors (the current
    /// ones and the spare), by their capacities. The same for any image size (issue 32: <= 64 MiB at 4K);
    /// each thread's record buffer (render/path_tracer.h PathScratch) comes on top.
    std::size_t bytes() const;

private:
    /// The next epoch begins: `epoch` up by one, its start's variance, rays, samples and paths.
    void startEpoch(double variancePerSample, std::uint64_t rays, std::uint64_t samples, std::uint64_t paths);

    SumTable sums_;
    CellSet occupied_;  ///< the cells of sums_ that hold records: all an epoch's end visits
    Factors spare_;     ///< the factors before the current ones: the next epoch's end refills their buffers
};

}  // namespace symphong::ears
