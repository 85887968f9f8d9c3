#include "splitting/ears.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace symphong {

const std::vector<std::string>& splittingNames() {
    static const std::vector<std::string> names = {"none", "ears"};
    return names;
}

SplittingMode splittingMode(const std::string& name) {
    if (name == "none") return SplittingMode::None;
    if (name == "ears") return SplittingMode::Ears;
    throw std::invalid_argument(fmt::format("unknown splitting '{}' (valid: {})", name, fmt::join(splittingNames(), ", ")));
}

void checkSplittingName(const std::string& name) { splittingMode(name); }

namespace ears {

namespace {

__extension__ typedef unsigned __int128 Wide;

constexpr double kFixedPoint = 1099511627776.0;  // 2^40: the unit of CellSums' values is 2^-40
constexpr double kMaxValue = 1e8;

Wide wide(const std::uint64_t (&w)[2]) { return (static_cast<Wide>(w[1]) << 64) | w[0]; }
void store(std::uint64_t (&w)[2], Wide v) {
    w[0] = static_cast<std::uint64_t>(v);
    w[1] = static_cast<std::uint64_t>(v >> 64);
}
Wide fixedPoint(double v) { return static_cast<Wide>(v * kFixedPoint); }
double toDouble(Wide v) { return static_cast<double>(v) / kFixedPoint; }

}  // namespace

double splittingFactor(double throughput, double varianceRatio, double momentRatio, double scale) {
    const double split = throughput * varianceRatio * scale;  // q_split = T sqrt(v / C_x) sqrt(C / V)
    const double roulette = throughput * momentRatio * scale;  // q_rr = T sqrt(M / C_x) sqrt(C / V)
    if (std::isnan(split) || std::isnan(roulette)) return kMinFactor;
    double q = 1;
    if (split > 1)
        q = split;
    else if (roulette < 1)
        q = roulette;
    if (!(q >= kMinFactor)) return kMinFactor;  // NaN too
    return std::min(q, kMaxFactor);
}

void CellSums::add(double value, std::uint64_t rays) {
    if (!(value >= 0)) value = 0;
    value = std::min(value, kMaxValue);
    ++count;
    cost += rays;
    store(values, wide(values) + fixedPoint(value));
    // value^2 in units of 2^-40 without overflowing a double's exactness: (value 2^20)^2.
    const double scaled = value * 1048576.0;
    store(squares, wide(squares) + static_cast<Wide>(scaled * scaled));
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

std::size_t Grid::cellCount() {
    std::size_t n = 0;
    for (int r : kResolution) n += static_cast<std::size_t>(r) * r * r;
    return n;
}

std::size_t Grid::cell(const Vec3& p, int level) const {
    std::size_t first = 0;
    for (int l = 0; l < level; ++l) first += static_cast<std::size_t>(kResolution[l]) * kResolution[l] * kResolution[l];
    const int r = kResolution[static_cast<std::size_t>(level)];
    const auto index = [&](double x, double lo, double inv) {
        const double t = (x - lo) * inv * r;
        if (!(t > 0)) return std::size_t{0};  // NaN too
        return static_cast<std::size_t>(std::min(t, r - 1.0));
    };
    const std::size_t ix = index(p.x, lo_.x, inverseSize_.x), iy = index(p.y, lo_.y, inverseSize_.y), iz = index(p.z, lo_.z, inverseSize_.z);
    return first + (iz * static_cast<std::size_t>(r) + iy) * static_cast<std::size_t>(r) + ix;
}

long Factors::cellAt(const Grid& grid, const Vec3& p) const {
    for (int level = Grid::kLevels - 1; level >= 0; --level) {
        const std::size_t c = grid.cell(p, level);
        if (momentRatio[c] >= 0) return static_cast<long>(c);
    }
    return -1;
}

Factors learnFactors(const std::vector<CellSums>& sums, double costPerSample, double variancePerSample) {
    Factors f;
    if (!(variancePerSample > 0) || !(costPerSample > 0) || !std::isfinite(variancePerSample)) return f;
    f.scale = std::sqrt(costPerSample / variancePerSample);
    f.varianceRatio.assign(sums.size(), -1.0f);
    f.momentRatio.assign(sums.size(), -1.0f);
    for (std::size_t c = 0; c < sums.size(); ++c) {
        const CellSums& s = sums[c];
        if (s.count < kMinRecords) continue;
        const double m = s.secondMoment(), mean = s.mean(), cost = std::max(1.0, s.meanCost());
        const double unbiased = static_cast<double>(s.count) / static_cast<double>(s.count - 1);
        f.varianceRatio[c] = static_cast<float>(std::sqrt(std::max(0.0, (m - mean * mean) * unbiased) / cost));
        f.momentRatio[c] = static_cast<float>(std::sqrt(m / cost));
    }
    return f;
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
