#include "splitting/learning.h"

#include <bit>

namespace symphong::ears {

int epochOf(std::uint32_t sample) { return sample < 2 ? 0 : static_cast<int>(std::bit_width(sample)) - 1; }

std::uint32_t epochEnd(std::uint32_t reached) {
    if (reached < 2) return 2;
    const int e = epochOf(reached);
    return e >= 31 ? 0xffffffffu : (1u << (e + 1));
}

std::uint32_t epochStart(int epoch) { return epoch == 0 ? 0u : epoch >= 32 ? 0xffffffffu : (1u << epoch); }

void Learning::add(const Record& r) {
    for (int level = 0; level < Grid::kLevels; ++level) sums[grid.cell(r.position, level)].add(r.value, r.rays);
}

void Learning::add(const std::vector<CellSums>& other) {
    for (std::size_t c = 0; c < sums.size() && c < other.size(); ++c)
        if (!other[c].empty()) sums[c].add(other[c]);
}

void Learning::advance(double variancePerSample, std::uint64_t rays, std::uint64_t samples) {
    const double cost = samples > samplesAtStart ? static_cast<double>(rays - raysAtStart) / static_cast<double>(samples - samplesAtStart) : 0;
    factors = learnFactors(sums, cost, variancePerSample);
    sums.assign(Grid::cellCount(), CellSums{});
    ++epoch;
    raysAtStart = rays;
    samplesAtStart = samples;
}

}  // namespace symphong::ears
