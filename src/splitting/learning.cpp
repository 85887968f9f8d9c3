#include "splitting/learning.h"

#include <algorithm>
#include <bit>

namespace symphong::ears {

int epochOf(std::uint32_t sample) { return sample < 2 ? 0 : static_cast<int>(std::bit_width(sample)) - 1; }

std::uint32_t epochEnd(std::uint32_t reached) {
    if (reached < 2) return 2;
    const int e = epochOf(reached);
    return e >= 31 ? 0xffffffffu : (1u << (e + 1));
}

std::uint32_t epochStart(int epoch) { return epoch == 0 ? 0u : epoch >= 32 ? 0xffffffffu : (1u << epoch); }

void Learning::clearSums() {
    if (sums_.size() != sumCount() || occupied_.capacity() < sumCount()) {
        sums_.assign(sumCount(), CellSums{});
        occupied_ = CellSet(sumCount());
        return;
    }
    occupied_.forEach(0, sumCount(), [&](std::size_t c) { sums_[c] = CellSums{}; });
    occupied_.clear();
}

std::size_t Learning::bytes() const {
    const auto factorBytes = [](const Factors& f) {
        std::size_t floats = 0;
        for (const std::vector<float>* table : f.tables()) floats += table->capacity();
        return floats * sizeof(float);
    };
    return sums_.capacity() * sizeof(CellSums) + occupied_.capacity() / 8 + factorBytes(factors) + factorBytes(spare_);
}

void Learning::add(std::size_t slot, const CellSums& s) {
    if (s.empty()) return;
    sums_[slot].add(s);
    occupied_.insert(slot);
}

void Learning::add(const Record& r) {
    sums_[r.slot].add(r.value, r.rays);  // the coarser cells at the epoch's end
    occupied_.insert(r.slot);
}

void Learning::add(const std::vector<Record>& records) {
    constexpr std::size_t kAhead = 16;
    // A cell's 48 bytes may span two cache lines: both fetched.
    const auto fetch = [&](const Record& r) {
        const char* cell = reinterpret_cast<const char*>(&sums_[r.slot]);
        __builtin_prefetch(cell, 1);
        __builtin_prefetch(cell + sizeof(CellSums) - 1, 1);
    };
    const std::size_t n = records.size();
    for (std::size_t i = 0; i < std::min(n, kAhead); ++i) fetch(records[i]);
    for (std::size_t i = 0; i < n; ++i) {
        if (i + kAhead < n) fetch(records[i + kAhead]);
        sums_[records[i].slot].add(records[i].value, records[i].rays);
        occupied_.insert(records[i].slot);
    }
}

void Learning::advance(double variancePerSample, std::uint64_t rays, std::uint64_t samples, std::uint64_t paths, bool mayRest) {
    EpochMeasure m;
    m.cameraSamples = static_cast<double>(samples - std::min(samples, samplesAtStart));
    // Rest when this epoch's vertices split (nearly) nothing: its extra paths, those beyond one per camera sample.
    if (mayRest && epoch >= kRestFromEpoch && paths != kUnknownPaths && pathsAtStart != kUnknownPaths && paths >= pathsAtStart &&
        m.cameraSamples > 0) {
        const double extra = static_cast<double>(paths - pathsAtStart) - m.cameraSamples;
        resting = extra < kRestBelowExtraPaths * m.cameraSamples;
    }
    if (resting) {
        // Nothing more is learned: the epoch's factors would never be used. Its sums go (a checkpoint from
        // now on carries none); the epoch and its start still move on, as at every epoch's end.
        clearSums();
        startEpoch(variancePerSample, rays, samples, paths);
        return;
    }
    m.costPerSample = m.cameraSamples > 0 ? static_cast<double>(rays - raysAtStart) / m.cameraSamples : 0;
    m.variancePerSample = epoch == 0 ? variancePerSample : std::max(2 * variancePerSample - varianceAtStart, 0.25 * variancePerSample);
    propagateToCoarserCells(sums_, occupied_);
    Factors next = learnFactors(sums_, m, occupied_, std::move(spare_));
    // After a probe (see kProbeSamples) the first hit's factors may fall at the end of epoch 0, never rise,
    // and hold from then on; its MIS shares are epoch 0's (the probe's where epoch 0 has none), held as well
    // (no first-hit records after epoch 0).
    if (probed && !factors.empty() && !next.empty()) {
        if (epoch == 0) {
            for (std::size_t c = 0; c < next.firstHit.size(); ++c) {
                if (factors.firstHit[c] >= 0 && (next.firstHit[c] < 0 || factors.firstHit[c] < next.firstHit[c])) next.firstHit[c] = factors.firstHit[c];
                if (next.misShare[c] < 0) next.misShare[c] = factors.misShare[c];
            }
        } else {
            std::swap(next.firstHit, factors.firstHit);
            std::swap(next.misShare, factors.misShare);
        }
    }
    spare_ = std::move(factors);
    factors = std::move(next);
    clearSums();
    startEpoch(variancePerSample, rays, samples, paths);
}

void Learning::startEpoch(double variancePerSample, std::uint64_t rays, std::uint64_t samples, std::uint64_t paths) {
    varianceAtStart = variancePerSample;
    ++epoch;
    raysAtStart = rays;
    samplesAtStart = samples;
    pathsAtStart = paths;
}

void Learning::learnFromProbe(double variancePerSample, std::uint64_t rays, std::uint64_t samples) {
    EpochMeasure m;
    m.cameraSamples = static_cast<double>(samples);
    m.costPerSample = samples > 0 ? static_cast<double>(rays) / static_cast<double>(samples) : 0;
    m.variancePerSample = variancePerSample;
    propagateToCoarserCells(sums_, occupied_);
    factors = learnFactors(sums_, m, occupied_);
    // Deeper vertices go unlearned through epoch 0 (the first hit's factors and MIS shares are the probe's),
    // as without a probe: the probe's few pixels measure the
    // image's variance V too unevenly for the scale sqrt(C / V) that every deeper factor takes (seeds whose
    // probe missed the rare bright paths split every bounce up to 8 times).
    std::fill(factors.varianceRatio.begin(), factors.varianceRatio.end(), -1.0f);
    std::fill(factors.momentRatio.begin(), factors.momentRatio.end(), -1.0f);
    clearSums();
    probed = true;
}

}  // namespace symphong::ears
