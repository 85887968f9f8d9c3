// splitting/ — efficiency-aware Russian roulette and splitting (EARS: Rath, Grittmann, Herholz, Weier and
// Slusallek, ACM TOG 41(4), 2022): how many continuations a path vertex gets, learned from the render's
// own earlier samples. Owns the formula of the factor, the learned structure (a grid over the scene's
// bounds at several resolutions), its statistics, kept exactly in integers so that the learned factors do
// not depend on the order in which threads or ranks add to them, the schedule of learning (epochs of
// doubling sample counts, splitting/learning.h), the share of a split first hit's continuations that its
// MIS counts (misShare), and the factors' fixed point on a model (for tests). It
// knows nothing of rays: the path tracer (render/) asks it for a factor at a point and tells it each
// continuation's value and cost. docs/estimators.md "Efficiency-aware splitting" derives the formula.
#pragma once

#include "math/branchless.h"
#include "math/vec3.h"
#include "util/large_buffer.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

namespace symphong {

/// How a path vertex decides how many continuations it gets.
enum class SplittingMode {
    None,       ///< one continuation, Russian roulette by throughput (render/path_tracer.h), --split at the first hit
    Ears,       ///< the learned factor of this file at every vertex; continuations are independent directions
    EarsOrbit,  ///< the same factors; a first hit's n = 2, 4 or 8 continuations are one symmetric orbit of R = n copies
};

/// Whether the mode learns factors (every mode but None).
inline bool learnsFactors(SplittingMode m) { return m != SplittingMode::None; }

/// "none", "ears", "ears-orbit": the names `--splitting` takes, in the order --help lists them.
const std::vector<std::string>& splittingNames();
/// The mode of a name; throws std::invalid_argument "unknown splitting 'x' (valid: none, ears, ears-orbit)".
SplittingMode splittingMode(const std::string& name);
void checkSplittingName(const std::string& name);
/// The name of a mode (splittingNames()'s entry).
const std::string& splittingName(SplittingMode m);

namespace ears {

inline constexpr double kMinFactor = 0.05;        ///< the least factor: a continuation survives at least 1 in 20
inline constexpr double kMaxFactor = 8;           ///< the most continuations a vertex gets
inline constexpr std::uint64_t kMinRecords = 32;  ///< a cell's estimate is used from this many continuations on
/// The first hit's factor where no cell has an estimate yet (all of epoch 0): pairs of continuations, for
/// the next epoch to learn the within-vertex variance from. (1.5, pairs at every other vertex, was
/// measured worse on five of six scenes of scripts/ears-study.sh: sky-n10 1.01x plain phong against 1.27x.)
inline constexpr double kUnknownFirstHitFactor = 2;

/// The efficiency-optimal factor of a vertex (EARS section 4, for the image's MSE):
///   q = T sqrt(S / C_x) sqrt(C / V),
/// T the luminance of the path's throughput up to the vertex (its weight in the pixel's estimate, the
/// 1/q of earlier vertices included), C_x the expected cost of one continuation from the vertex's region,
/// V the variance and C the cost of one camera sample (whole image), and S what one continuation adds to
/// V per unit of 1/q: its variance when splitting (q > 1: n continuations of variance v give v / n), its
/// second moment M under Russian roulette (q < 1: a survival probability q gives M / q - mean^2). So
/// q_split = T sqrt(v / C_x) sqrt(C/V) when that exceeds 1, else q_rr = T sqrt(M / C_x) sqrt(C/V) when that
/// is below 1, else 1 (the two disagree). `varianceRatio` is sqrt(v / C_x), `momentRatio` sqrt(M / C_x),
/// `scale` sqrt(C / V). Clamped to [kMinFactor, kMaxFactor]; NaN in, kMinFactor out.
/// Inline: once per path vertex, and without branches on the values (which of the three cases holds
/// changes from vertex to vertex: a branch on it was mispredicted at about one vertex in ten).
inline double splittingFactor(double throughput, double varianceRatio, double momentRatio, double scale) {
    const double split = throughput * varianceRatio * scale;           // q_split = T sqrt(v / C_x) sqrt(C / V)
    const double roulette = throughput * momentRatio * scale;          // q_rr = T sqrt(M / C_x) sqrt(C / V)
    if (std::isnan(split) || std::isnan(roulette)) return kMinFactor;  // never taken but on bad input
    // split > 1: split; else roulette < 1: roulette; else 1. As selects (minsd, then a blend).
    const double rouletteOrOne = roulette < 1 ? roulette : 1.0;
    const double q = split > 1 ? split : rouletteOrOne;
    return clampByMasks(q, kMinFactor, kMaxFactor);  // std::clamp's values, without its branches
}

/// Plain Russian roulette's survival probability at a vertex whose throughput's largest component is
/// `maxThroughput`: that, clamped to [kMinFactor, 0.95] (NaN: kMinFactor). The factor of a deeper vertex
/// with no learned cell, and the floor of a learned roulette factor under a low-discrepancy sampler.
/// Without a branch (the throughput is a vertex's, random): !(t >= kMinFactor) holds for a NaN t too.
inline double throughputSurvival(double maxThroughput) {
    const double atLeast = choose(!(maxThroughput >= kMinFactor), kMinFactor, maxThroughput);
    return choose(atLeast > 0.95, 0.95, atLeast);
}

/// A learned factor q with its roulette floored at plain roulette's survival `plain` (q < 1: the larger of
/// the two; splitting, q >= 1, unchanged). Under a low-discrepancy sampler the render's error is far below
/// the per-sample variance V that splittingFactor's scale sqrt(C / V) assumes (Owen-scrambled Sobol' on the
/// diffuse Cornell box at 64 spp: 1/15 of the independent sampler's MSE), while the variance that
/// roulette adds is not stratified away: the formula roulettes too hard there (docs/estimators.md
/// "Roulette under a low-discrepancy sampler"). The render applies it when its sampler is not
/// independent (TraceSettings::earsRouletteFloor).
/// `plain` < 1 (throughputSurvival's is at most 0.95), so that the larger of the two is the rule in both cases:
/// one max, no branch.
inline double flooredRoulette(double q, double plain) { return std::max(q, std::min(plain, 1.0)); }

/// The first hit's number of continuations for the model's optimum q: the power of two nearest to q on a
/// log scale (2^round(log2 q)), in [1, kMaxFactor]: the same at every vertex of a cell, and a whole block
/// of block points (SampleStream::blockContinuation), so that a pixel's first-hit continuations stay a net.
/// It is also the best power of two for the model: a cell's share of V x C near the optimum goes as
/// a / n + b n, whose ratio to its minimum, (q/n + n/q) / 2, depends on log(n / q) alone and symmetrically.
/// Inline and by three comparisons with the midpoints 2^(k + 1/2) on the log scale (once per first hit;
/// log2, round and exp2 were three calls into libm).
inline double firstHitBlock(double q) {
    static_assert(kMaxFactor == 8, "the blocks are 1, 2, 4 and 8");
    constexpr double kSqrt2 = 1.4142135623730950488;  // 2^(1/2): the midpoint of 1 and 2 on the log scale
    // q >= 2^(k + 1/2) adds 2^k: 1, 2, 4 or 8 (NaN compares false: 1).
    return 1.0 + (q >= kSqrt2 ? 1.0 : 0.0) + (q >= 2 * kSqrt2 ? 2.0 : 0.0) + (q >= 4 * kSqrt2 ? 4.0 : 0.0);
}

/// Exact sums of one region's continuations: their number, rays, values and squared values in units of
/// 2^-40 (unsigned 128-bit integers; values are clamped to [0, 2^23], so that a value fits 64 bits and its
/// square is one exact 64 x 64-bit product), so that adding the same records in
/// any order gives the same sums, bit for bit.
struct CellSums {
    std::uint64_t count = 0;
    std::uint64_t cost = 0;
    std::uint64_t values[2] = {0, 0};   ///< the 128-bit sum of values, low word first
    std::uint64_t squares[2] = {0, 0};  ///< the 128-bit sum of squared values, low word first

    void add(double value, std::uint64_t rays);
    void add(const CellSums& other);
    bool empty() const { return count == 0; }
    double mean() const;          ///< mean value (0 when empty)
    double secondMoment() const;  ///< mean of value^2 (0 when empty)
    double meanCost() const;      ///< mean rays (0 when empty)
};

/// An epoch's sums: kSections x Grid::cellCount() cells (7.2 MB), on huge pages where the system offers them
/// (util/large_buffer.h: first touched by every render that learns).
using SumTable = LargeBufferVector<CellSums>;

/// The regions: a grid over a box at resolutions 4, 8, 16 and 32 cells a side; a point lies in one cell
/// of each level. A vertex uses the finest of its cells whose estimate rests on kMinRecords continuations.
class Grid {
public:
    static constexpr int kLevels = 4;
    static constexpr std::array<int, kLevels> kResolution = {4, 8, 16, 32};
    static_assert(std::all_of(kResolution.begin(), kResolution.end(), [](int r) { return std::has_single_bit(static_cast<unsigned>(r)); }),
                  "Grid::ancestor works by shifts");

    Grid() = default;
    /// The box [lo, hi], widened by 0.1% of its diagonal on every side (points on its faces lie inside).
    Grid(const Vec3& lo, const Vec3& hi);
    /// The grid over exactly [lo, hi] (a checkpoint's grid: lo() and hi() of the one it was made with).
    static Grid fromBox(const Vec3& lo, const Vec3& hi);

    /// Cells of every level together (37,440).
    static constexpr std::size_t cellCount() { return firstCell(kLevels); }
    /// The index of `p`'s cell at `level` (points outside the box: its nearest cell). Inline: once per
    /// path vertex.
    std::size_t cell(const Vec3& p, int level) const {
        const int r = kResolution[static_cast<std::size_t>(level)];
        const auto index = [r](double x, double lo, double inv) {
            const double t = (x - lo) * inv * r;
            // Clamped to [0, r - 1] after the conversion, in integers (conditional moves: which wall of
            // the box a vertex lies on, and so whether it is in the last cell, changes from vertex to
            // vertex; GCC made the same clamp of the double a branch). The conversion to a signed 64-bit
            // integer is one instruction and gives INT64_MIN for a NaN (clamped to 0); a point of the scene
            // has |t| far below 2^63.
            const long long i = static_cast<long long>(t);
            return static_cast<std::size_t>(std::min<long long>(std::max<long long>(i, 0), r - 1));
        };
        const std::size_t ix = index(p.x, lo_.x, inverseSize_.x), iy = index(p.y, lo_.y, inverseSize_.y),
                          iz = index(p.z, lo_.z, inverseSize_.z);
        return firstCell(level) + (iz * static_cast<std::size_t>(r) + iy) * static_cast<std::size_t>(r) + ix;
    }
    /// The first cell of `level` (cells of a level are numbered x fastest, then y, then z).
    static constexpr std::size_t firstCell(int level) {
        std::size_t first = 0;
        for (int l = 0; l < level; ++l) first += static_cast<std::size_t>(kResolution[l]) * kResolution[l] * kResolution[l];
        return first;
    }
    /// The cell of `level` that holds cell `finest` of the finest level. Inline, by shifts (every level's
    /// resolution is a power of two): the end of an epoch asks it about every finest cell.
    static std::size_t ancestor(std::size_t finest, int level) {
        constexpr int fineBits = std::countr_zero(static_cast<unsigned>(kResolution[kLevels - 1]));
        constexpr std::size_t fineMask = (std::size_t{1} << fineBits) - 1;
        const std::size_t i = finest - firstCell(kLevels - 1);
        const int bits = std::countr_zero(static_cast<unsigned>(kResolution[static_cast<std::size_t>(level)]));
        const int shift = fineBits - bits;
        const std::size_t ix = (i & fineMask) >> shift, iy = ((i >> fineBits) & fineMask) >> shift, iz = (i >> (2 * fineBits)) >> shift;
        return firstCell(level) + (((iz << bits) + iy) << bits) + ix;
    }
    const Vec3& lo() const { return lo_; }
    const Vec3& hi() const { return hi_; }

private:
    Vec3 lo_, hi_, inverseSize_;
};

/// A set of a SumTable's cells, one bit a cell: the cells that hold records, kept as records arrive
/// (Learning), so that the end of an epoch carries up, reads and clears those cells alone instead of the
/// whole 7.2 MB table (a scene's surfaces cross a small part of the grid: the Cornell box's about a fifth
/// of the finest cells). Visited in increasing order, as a scan of the table would visit them.
class CellSet {
public:
    CellSet() = default;
    explicit CellSet(std::size_t cells) : words_((cells + 63) / 64, 0) {}

    void insert(std::size_t c) { words_[c >> 6] |= std::uint64_t{1} << (c & 63); }
    bool contains(std::size_t c) const { return c >> 6 < words_.size() && ((words_[c >> 6] >> (c & 63)) & 1) != 0; }
    void clear() { std::fill(words_.begin(), words_.end(), 0); }
    /// The cells it can hold: [0, capacity()).
    std::size_t capacity() const { return words_.size() * 64; }
    /// fn(c) for every c of the set in [from, to), in increasing order. fn may insert cells outside the range.
    template <class Fn>
    void forEach(std::size_t from, std::size_t to, Fn&& fn) const {
        to = std::min(to, capacity());
        for (std::size_t w = from >> 6; w << 6 < to; ++w) {
            std::uint64_t bits = words_[w];
            if (w == from >> 6) bits &= ~std::uint64_t{0} << (from & 63);
            while (bits) {
                const std::size_t c = (w << 6) + static_cast<std::size_t>(std::countr_zero(bits));
                if (c >= to) return;
                fn(c);
                bits &= bits - 1;
            }
        }
    }

private:
    std::vector<std::uint64_t> words_;
};

/// The cells of `sums` that hold records, by a scan of the whole table.
CellSet occupiedCells(const SumTable& sums);

/// What the sums of an epoch hold, in four sections of Grid::cellCount() cells each (Learning::sums):
///  - Deeper: continuations of vertices after the first hit (count, rays, values and squares);
///  - FirstHit: continuations of first-hit vertices (the same);
///  - FirstHitVertex: first-hit vertices, one record each: count = vertices, cost = those with two or more
///    continuations, values = the sum of their continuations' sample variances (the within-vertex
///    variance, which splitting divides by n; the spread of means across a cell, which it does not, is
///    left out);
///  - BrdfHit: first-hit continuations, one record each: the luminance of f cos / p times the emission its
///    ray met at the next vertex (0 when it met none that light sampling could also have found), cost 1
///    when it met some: the share of continuations that find a light, for misShare.
enum class Section : std::uint8_t { Deeper = 0, FirstHit = 1, FirstHitVertex = 2, BrdfHit = 3 };
inline constexpr int kSections = 4;
/// The first slot of a section in the sums (and in a CellSet of them): cell c of it is slot start + c.
inline std::size_t sectionStart(Section section) { return Grid::cellCount() * static_cast<std::size_t>(section); }

/// The first hit's continuations find a light at most this often (a share of them) where its MIS counts
/// one estimator call however many continuations the vertex has, and at least kFoldedHitRate where it
/// counts all of them (linearly in between): see misShare.
inline constexpr double kUnfoldedHitRate = 0.25;
inline constexpr double kFoldedHitRate = 0.5;

/// The share t in [0, 1] of a first hit's continuations beyond the first that its MIS counts, from a
/// cell's BrdfHit sums: its n continuations stand for 1 + (n - 1) t estimator calls in the power heuristic
/// against light sampling's one (PathTracer::misScale). t = 0 where at most kUnfoldedHitRate of the
/// continuations found a light, 1 from kFoldedHitRate on, linear in between; -1 (no estimate: all of
/// them, the plain count) below kMinRecords records. Where the BRDF's directions seldom find the light
/// (a small or distant light) each is a rare bright hit, and counting n of them against one light sample
/// gives those hits weight that light sampling would have spent better (docs/estimators.md "MIS at a
/// split first hit"); where they mostly do (a sky), the count is what makes splitting pay.
double misShare(const CellSums& brdf);

/// What a render learned for an epoch: per cell sqrt(v / C_x) and sqrt(M / C_x) of the deeper vertices,
/// the first hit's factor q and its MIS share (misShare) (negative: too few records to say), and the scale
/// sqrt(C / V) at the optimum. Every finest cell holds its nearest estimate (its own, else its nearest
/// coarser cell's: learnFactors fills them in), so a finest cell's entry is what cellAt finds; the path
/// tracer reads it directly.
struct Factors {
    std::vector<float> varianceRatio, momentRatio, firstHit, misShare;
    double scale = 0;

    bool empty() const { return momentRatio.empty(); }
    /// The tables, in the order a checkpoint stores a cell's values: for code that treats them alike (its
    /// size, a checkpoint, a broadcast to ranks), so that a table added here reaches all of it.
    static constexpr std::size_t kTables = 4;
    std::array<std::vector<float>*, kTables> tables() { return {&varianceRatio, &momentRatio, &firstHit, &misShare}; }
    std::array<const std::vector<float>*, kTables> tables() const { return {&varianceRatio, &momentRatio, &firstHit, &misShare}; }
    /// Every table `cells` entries of -1: no estimate in any cell.
    void reset(std::size_t cells) {
        for (std::vector<float>* table : tables()) table->assign(cells, -1.0f);
    }
    /// The cell whose entry of `table` (momentRatio or firstHit) a vertex at p uses: its finest cell with
    /// an estimate; -1 when none has one.
    static long cellAt(const std::vector<float>& table, std::size_t finest);
    static long cellAt(const std::vector<float>& table, const Grid& grid, const Vec3& p) {
        return cellAt(table, grid.cell(p, Grid::kLevels - 1));
    }
    long cellAt(const Grid& grid, const Vec3& p) const { return cellAt(momentRatio, grid, p); }
    /// Whether learnFactors can put v in `table` (one of tables()): -1 (no estimate) or a finite number >= 0,
    /// the first hit's factor in [1, kMaxFactor], its MIS share in [0, 1]. What a checkpoint's factors must be.
    bool learnedValue(const std::vector<float>& table, float v) const {
        if (v == -1.0f) return true;
        if (!(v >= 0) || !std::isfinite(v)) return false;
        if (&table == &firstHit) return v >= 1 && v <= kMaxFactor;
        return &table != &misShare || v <= 1;
    }
};

/// What a render measured over one epoch: the sums (kSections x Grid::cellCount()), the cost C of a
/// camera sample (rays), the variance V of its estimate (per pixel, averaged over the image) and the
/// number of camera samples.
struct EpochMeasure {
    double costPerSample = 0, variancePerSample = 0, cameraSamples = 0;
};

/// The factors learned from one epoch. Deeper vertices: EARS's ratios per cell, used with the scale by
/// splittingFactor. The first hit: the optimum of the model V(q) = V0 + sum_c n_c v_c / q_c,
/// C(q) = C0 + sum_c n_c q_c C_c over its cells c (n_c first-hit vertices per camera sample, v_c their
/// within-vertex variance, C_c the rays of one continuation; V0 and C0 what the epoch measured less the
/// first hit's continuations at the factors it had), solved at once rather than one step per epoch:
/// q_c = lambda sqrt(v_c / C_c) clamped to [1, kMaxFactor] with lambda^2 = C(q) / V(q) (found by
/// bisection); lambda is the scale (a vertex takes firstHitBlock(q_c) continuations). No factors at all
/// when V is not positive.
/// `occupied`: the cells of `sums` that hold records (every other cell is taken to be empty); without it,
/// a scan of the table finds them. `storage`: factors whose buffers the result takes over (their values do
/// not matter), so that each epoch's end refills the last one's memory instead of touching fresh pages.
Factors learnFactors(const SumTable& sums, const EpochMeasure& epoch, const CellSet& occupied, Factors storage = {});
Factors learnFactors(const SumTable& sums, const EpochMeasure& epoch);

/// Sums of the finest cells (where Learning::add puts records) added into every coarser cell that holds
/// them, section by section (sums: whole sections of Grid::cellCount() cells). `occupied`: the cells that
/// hold records (every other is taken to be empty), the coarser cells that receive some added to it;
/// without it, a scan of the table finds them.
void propagateToCoarserCells(SumTable& sums, CellSet& occupied);
void propagateToCoarserCells(SumTable& sums);

/// A model of an image for the fixed point: per camera sample, `visits` vertices of this region with
/// throughput `throughput`, whose continuations have variance `variance` and cost `cost` (and mean 0, so
/// that the variance is the second moment too and one formula holds for splitting and roulette).
struct ModelRegion {
    double visits = 0, throughput = 0, variance = 0, cost = 0;
};

/// The model's variance and cost of a camera sample under factors q: V = V0 + sum visits T^2 v / q,
/// C = C0 + sum visits q C_x.
void modelVarianceAndCost(double baseVariance, double baseCost, const std::vector<ModelRegion>& regions, const std::vector<double>& q,
                          double& variance, double& cost);

/// EARS's fixed point on the model: q = 1 everywhere, then `iterations` times each region's factor from
/// splittingFactor with the V and C that the previous factors give (what a render does from epoch to
/// epoch). The result is the minimum of V x C, sqrt(C0/V0) T sqrt(M/C_x) when no clamp applies.
std::vector<double> modelFixedPoint(double baseVariance, double baseCost, const std::vector<ModelRegion>& regions, int iterations);

}  // namespace ears
}  // namespace symphong
