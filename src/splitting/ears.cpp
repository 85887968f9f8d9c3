#include "splitting/ears.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace symphong {

const std::vector<std::string>& splittingNames() {
    static const std::vector<std::string> names = {"none", "ears", "ears-orbit"};
    return names;
}

SplittingMode splittingMode(const std::string& name) {
    if (name == "none") return SplittingMode::None;
    if (name == "ears") return SplittingMode::Ears;
    if (name == "ears-orbit") return SplittingMode::EarsOrbit;
    throw std::invalid_argument(fmt::format("unknown splitting '{}' (valid: {})", name, fmt::join(splittingNames(), ", ")));
}

void checkSplittingName(const std::string& name) { splittingMode(name); }

const std::string& splittingName(SplittingMode m) { return splittingNames().at(static_cast<std::size_t>(m)); }

namespace ears {

namespace {

__extension__ typedef unsigned __int128 Wide;

constexpr double kFixedPoint = 1099511627776.0;  // 2^40: the unit of CellSums' values is 2^-40
constexpr double kMaxValue = 8388608.0;          // 2^23: value 2^40 < 2^63

Wide wide(const std::uint64_t (&w)[2]) { return (static_cast<Wide>(w[1]) << 64) | w[0]; }
void store(std::uint64_t (&w)[2], Wide v) {
    w[0] = static_cast<std::uint64_t>(v);
    w[1] = static_cast<std::uint64_t>(v >> 64);
}
double toDouble(Wide v) { return static_cast<double>(v) / kFixedPoint; }

}  // namespace

void CellSums::add(double value, std::uint64_t rays) {
    if (!(value >= 0)) value = 0;
    value = std::min(value, kMaxValue);
    ++count;
    cost += rays;
    // value in units of 2^-40 (< 2^63), and its square from value in units of 2^-20 (< 2^43), squared exactly.
    store(values, wide(values) + static_cast<std::uint64_t>(value * kFixedPoint));
    const auto scaled = static_cast<std::uint64_t>(value * 1048576.0);
    store(squares, wide(squares) + static_cast<Wide>(scaled) * scaled);
}

void CellSums::add(const CellSums& o) {
    count += o.count;
    cost += o.cost;
    store(values, wide(values) + wide(o.values));
    store(squares, wide(squares) + wide(o.squares));
}

double CellSums::mean() const { return count ? toDouble(wide(values)) / static_cast<double>(count) : 0.0; }
double CellSums::secondMoment() const { return count ? toDouble(wide(squares)) / static_cast<double>(count) : 0.0; }
double CellSums::meanCost() const { return count ? static_cast<double>(cost) / static_cast<double>(count) : 0.0; }

double misShare(const CellSums& brdf) {
    if (brdf.count < kMinRecords) return -1;
    const double rate = static_cast<double>(brdf.cost) / static_cast<double>(brdf.count);
    return std::clamp((rate - kUnfoldedHitRate) / (kFoldedHitRate - kUnfoldedHitRate), 0.0, 1.0);
}

Grid::Grid(const Vec3& lo, const Vec3& hi) {
    const Vec3 margin(1e-3 * std::max(length(hi - lo), 1e-6));
    *this = fromBox(lo - margin, hi + margin);
}

Grid Grid::fromBox(const Vec3& lo, const Vec3& hi) {
    Grid g;
    g.lo_ = lo, g.hi_ = hi;
    const Vec3 size = hi - lo;
    g.inverseSize_ = Vec3(1.0 / size.x, 1.0 / size.y, 1.0 / size.z);
    return g;
}

long Factors::cellAt(const std::vector<float>& table, std::size_t finest) {
    if (table[finest] >= 0) return static_cast<long>(finest);
    for (int level = Grid::kLevels - 2; level >= 0; --level) {
        const std::size_t c = Grid::ancestor(finest, level);
        if (table[c] >= 0) return static_cast<long>(c);
    }
    return -1;
}

namespace {

/// The first hit's cells as the model sees them: per cell its vertices and continuations per camera
/// sample, within-vertex variance and rays per continuation.
struct FirstHitCell {
    double vertices = 0, continuations = 0, variance = 0, cost = 0;
};

/// The variance a cell's first-hit vertices would have per continuation (-1: too few to say): the mean
/// within-vertex variance where enough vertices had two or more continuations, else the variance of all
/// its continuations (which also holds the spread of means across the cell: too high, so the next epoch
/// splits more and measures the within-vertex part).
double firstHitVariance(const CellSums& continuations, const CellSums& vertices) {
    if (vertices.count < kMinRecords || continuations.count < 2) return -1;
    if (vertices.cost >= kMinRecords) return vertices.mean() * static_cast<double>(vertices.count) / static_cast<double>(vertices.cost);
    const double n = static_cast<double>(continuations.count);
    return std::max(0.0, (continuations.secondMoment() - continuations.mean() * continuations.mean()) * n / (n - 1));
}

/// The model's V x C optimum over the first hit's cells: lambda with lambda^2 V(lambda) = C(lambda), by
/// bisection on log lambda (lambda^2 V - C grows with lambda: the terms of unclamped cells cancel).
double solveScale(double v0, double c0, const std::vector<FirstHitCell>& cells) {
    // What every step of the bisection needs of a cell, computed once (the same values, bit for bit).
    struct Term {
        double ratio, weightedVariance, vertices, cost;  // sqrt(v / C_c), n v, n, C_c
    };
    std::vector<Term> terms;
    terms.reserve(cells.size());
    for (const FirstHitCell& m : cells) terms.push_back({std::sqrt(m.variance / m.cost), m.vertices * m.variance, m.vertices, m.cost});
    const auto gap = [&](double lambda) {
        double v = v0, c = c0;
        for (const Term& t : terms) {
            const double q = std::clamp(lambda * t.ratio, 1.0, kMaxFactor);
            v += t.weightedVariance / q;
            c += t.vertices * q * t.cost;
        }
        return lambda * lambda * v - c;
    };
    double lo = std::log(1e-9), hi = std::log(1e9);
    if (gap(std::exp(hi)) <= 0) return std::exp(hi);
    for (int i = 0; i < 80; ++i) {
        const double mid = 0.5 * (lo + hi);
        // lo and hi neighbours (mid is one of them): every later step would repeat this one or do nothing.
        const bool last = mid == lo || mid == hi;
        (gap(std::exp(mid)) < 0 ? lo : hi) = mid;
        if (last) break;
    }
    return std::exp(0.5 * (lo + hi));
}

}  // namespace

CellSet occupiedCells(const SumTable& sums) {
    CellSet set(sums.size());
    for (std::size_t c = 0; c < sums.size(); ++c)
        if (!sums[c].empty()) set.insert(c);
    return set;
}

Factors learnFactors(const SumTable& sums, const EpochMeasure& epoch) { return learnFactors(sums, epoch, occupiedCells(sums)); }

namespace {

/// Every cell's first-hit variance (ears::firstHitVariance; -1 where it has no estimate): only a cell
/// with first-hit vertices has one, so only those are visited.
std::vector<float> firstHitVariances(const SumTable& sums, const CellSet& occupied) {
    const std::size_t cells = Grid::cellCount(), vertexSlot = sectionStart(Section::FirstHitVertex);
    const CellSums* firstHit = sums.data() + sectionStart(Section::FirstHit);
    const CellSums* vertices = sums.data() + vertexSlot;
    std::vector<float> variance(cells, -1.0f);
    occupied.forEach(vertexSlot, vertexSlot + cells, [&](std::size_t slot) {
        const std::size_t c = slot - vertexSlot;
        variance[c] = static_cast<float>(firstHitVariance(firstHit[c], vertices[c]));
    });
    return variance;
}

/// Deeper vertices' ratios sqrt(variance / cost) and sqrt(second moment / cost) of the cells with
/// kMinRecords records or more (-1 elsewhere).
void deeperRatios(const SumTable& sums, const CellSet& occupied, Factors& f) {
    const std::size_t cells = Grid::cellCount(), deeperSlot = sectionStart(Section::Deeper);
    const CellSums* deeper = sums.data() + deeperSlot;
    occupied.forEach(deeperSlot, deeperSlot + cells, [&](std::size_t slot) {
        const std::size_t c = slot - deeperSlot;
        const CellSums& s = deeper[c];
        if (s.count < kMinRecords) return;
        const double m = s.secondMoment(), mean = s.mean(), cost = std::max(1.0, s.meanCost());
        const double unbiased = static_cast<double>(s.count) / static_cast<double>(s.count - 1);
        f.varianceRatio[c] = static_cast<float>(std::sqrt(std::max(0.0, (m - mean * mean) * unbiased) / cost));
        f.momentRatio[c] = static_cast<float>(std::sqrt(m / cost));
    });
}

/// The model's cells: every finest cell's vertices counted once, in the cell whose estimate they use
/// (the finest cell itself or its nearest ancestor with an estimate). A finest cell with none stays in
/// V0 and C0 at its factor (kept next epoch).
std::vector<FirstHitCell> firstHitModel(const SumTable& sums, const CellSet& occupied, const std::vector<float>& variance, double N) {
    const std::size_t cells = Grid::cellCount(), vertexSlot = sectionStart(Section::FirstHitVertex);
    const CellSums* firstHit = sums.data() + sectionStart(Section::FirstHit);
    const CellSums* vertices = sums.data() + vertexSlot;
    std::vector<FirstHitCell> model;
    std::vector<long> modelIndex(cells, -1);
    const std::size_t finest = Grid::firstCell(Grid::kLevels - 1);
    occupied.forEach(vertexSlot + finest, vertexSlot + cells, [&](std::size_t slot) {
        const std::size_t c = slot - vertexSlot;
        if (vertices[c].count == 0) return;
        long used = -1;
        for (int level = Grid::kLevels - 1; level >= 0 && used < 0; --level)
            if (const std::size_t a = Grid::ancestor(c, level); variance[a] >= 0) used = static_cast<long>(a);
        if (used < 0) return;
        const double n = static_cast<double>(vertices[c].count) / N, k = static_cast<double>(firstHit[c].count) / N;
        const auto u = static_cast<std::size_t>(used);
        if (modelIndex[u] < 0) {
            modelIndex[u] = static_cast<long>(model.size());
            model.push_back({0, 0, variance[u], std::max(1.0, firstHit[u].meanCost())});
        }
        FirstHitCell& m = model[static_cast<std::size_t>(modelIndex[u])];
        m.vertices += n, m.continuations += k;
    });
    return model;
}

/// A finest cell without an estimate of its own takes its nearest coarser cell's (what cellAt would
/// find), so that a vertex looks up one cell. First every coarser cell's nearest cell with an estimate
/// (itself or one holding it), level by level from the coarsest (a cell's parent resolved before it),
/// then each finest cell's from its parent's: one step a cell instead of a walk up the levels for each
/// of the 32,768 finest cells.
void fillFromCoarserCells(Factors& f) {
    const std::size_t cells = Grid::cellCount(), finest = Grid::firstCell(Grid::kLevels - 1);
    std::vector<std::int32_t> nearestMoment(finest, -1), nearestFirstHit(finest, -1), nearestShare(finest, -1);
    for (int level = 0; level < Grid::kLevels - 1; ++level) {
        const auto r = static_cast<std::size_t>(Grid::kResolution[static_cast<std::size_t>(level)]);
        const std::size_t first = Grid::firstCell(level), parentFirst = level > 0 ? Grid::firstCell(level - 1) : 0;
        for (std::size_t i = 0; i < r * r * r; ++i) {
            const std::size_t c = first + i;
            std::int32_t moment = f.momentRatio[c] >= 0 ? static_cast<std::int32_t>(c) : -1;
            std::int32_t hit = f.firstHit[c] >= 0 ? static_cast<std::int32_t>(c) : -1;
            std::int32_t mis = f.misShare[c] >= 0 ? static_cast<std::int32_t>(c) : -1;
            if (level > 0 && (moment < 0 || hit < 0 || mis < 0)) {
                const std::size_t ix = i % r, iy = i / r % r, iz = i / (r * r), half = r / 2;
                const std::size_t parent = parentFirst + (iz / 2 * half + iy / 2) * half + ix / 2;
                if (moment < 0) moment = nearestMoment[parent];
                if (hit < 0) hit = nearestFirstHit[parent];
                if (mis < 0) mis = nearestShare[parent];
            }
            nearestMoment[c] = moment, nearestFirstHit[c] = hit, nearestShare[c] = mis;
        }
    }
    for (std::size_t c = finest; c < cells; ++c) {
        if (f.momentRatio[c] >= 0 && f.firstHit[c] >= 0 && f.misShare[c] >= 0) continue;
        const std::size_t parent = Grid::ancestor(c, Grid::kLevels - 2);
        if (const std::int32_t a = nearestMoment[parent]; f.momentRatio[c] < 0 && a >= 0)
            f.momentRatio[c] = f.momentRatio[static_cast<std::size_t>(a)], f.varianceRatio[c] = f.varianceRatio[static_cast<std::size_t>(a)];
        if (const std::int32_t a = nearestFirstHit[parent]; f.firstHit[c] < 0 && a >= 0) f.firstHit[c] = f.firstHit[static_cast<std::size_t>(a)];
        if (const std::int32_t a = nearestShare[parent]; f.misShare[c] < 0 && a >= 0)
            f.misShare[c] = f.misShare[static_cast<std::size_t>(a)];
    }
}

}  // namespace

Factors learnFactors(const SumTable& sums, const EpochMeasure& epoch, const CellSet& occupied, Factors storage) {
    const double V = epoch.variancePerSample, C = epoch.costPerSample, N = epoch.cameraSamples;
    if (!(V > 0) || !(C > 0) || !(N > 0) || !std::isfinite(V)) return Factors{};
    Factors f = std::move(storage);
    const std::size_t cells = Grid::cellCount(), vertexSlot = sectionStart(Section::FirstHitVertex);
    const CellSums* firstHit = sums.data() + sectionStart(Section::FirstHit);
    f.reset(cells);
    const std::vector<float> variance = firstHitVariances(sums, occupied);
    deeperRatios(sums, occupied, f);
    const std::vector<FirstHitCell> model = firstHitModel(sums, occupied, variance, N);
    // V0 and C0: what remains of V and C without the first hit's continuations at their epoch's factors.
    // At those factors q_old = continuations / vertices a cell added n v / q_old to V and n q_old C_c to C.
    double v0 = V, c0 = C;
    for (const FirstHitCell& m : model) {
        if (m.continuations > 0) v0 -= m.vertices * m.vertices * m.variance / m.continuations;
        c0 -= m.continuations * m.cost;
    }
    v0 = std::max(v0, 0.02 * V);
    c0 = std::max(c0, 1.0);
    f.scale = model.empty() ? std::sqrt(C / V) : solveScale(v0, c0, model);
    occupied.forEach(vertexSlot, vertexSlot + cells, [&](std::size_t slot) {
        const std::size_t c = slot - vertexSlot;
        if (variance[c] >= 0)
            f.firstHit[c] = static_cast<float>(
                std::clamp(f.scale * std::sqrt(variance[c] / std::max(1.0, firstHit[c].meanCost())), 1.0, kMaxFactor));
    });
    // The first hit's MIS shares, in every cell (of every level) that holds its continuations.
    const std::size_t brdfSlot = sectionStart(Section::BrdfHit);
    occupied.forEach(brdfSlot, brdfSlot + cells,
                     [&](std::size_t slot) { f.misShare[slot - brdfSlot] = static_cast<float>(misShare(sums[slot])); });
    fillFromCoarserCells(f);
    return f;
}

void propagateToCoarserCells(SumTable& sums) {
    CellSet occupied = occupiedCells(sums);
    propagateToCoarserCells(sums, occupied);
}

void propagateToCoarserCells(SumTable& sums, CellSet& occupied) {
    const std::size_t cells = Grid::cellCount(), finest = Grid::firstCell(Grid::kLevels - 1);
    for (std::size_t base = 0; base + cells <= sums.size(); base += cells)
        occupied.forEach(base + finest, base + cells, [&](std::size_t slot) {
            if (sums[slot].empty()) return;
            for (int level = 0; level < Grid::kLevels - 1; ++level) {
                const std::size_t coarse = base + Grid::ancestor(slot - base, level);
                sums[coarse].add(sums[slot]);
                occupied.insert(coarse);
            }
        });
}

void modelVarianceAndCost(double baseVariance, double baseCost, const std::vector<ModelRegion>& regions, const std::vector<double>& q,
                          double& variance, double& cost) {
    variance = baseVariance, cost = baseCost;
    for (std::size_t r = 0; r < regions.size(); ++r) {
        const ModelRegion& m = regions[r];
        variance += m.visits * m.throughput * m.throughput * m.variance / q[r];
        cost += m.visits * q[r] * m.cost;
    }
}

std::vector<double> modelFixedPoint(double baseVariance, double baseCost, const std::vector<ModelRegion>& regions, int iterations) {
    std::vector<double> q(regions.size(), 1.0);
    for (int i = 0; i < iterations; ++i) {
        double v = 0, c = 0;
        modelVarianceAndCost(baseVariance, baseCost, regions, q, v, c);
        const double scale = std::sqrt(c / v);
        for (std::size_t r = 0; r < regions.size(); ++r) {
            const double ratio = std::sqrt(regions[r].variance / regions[r].cost);
            q[r] = splittingFactor(regions[r].throughput, ratio, ratio, scale);
        }
    }
    return q;
}

}  // namespace ears
}  // namespace symphong
