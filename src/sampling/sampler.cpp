#include "sampling/sampler.h"

#include "sampling/lowdiscrepancy.h"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

namespace symphong {

namespace {

std::uint32_t low32(std::uint64_t h) { return static_cast<std::uint32_t>(h); }
std::uint32_t high32(std::uint64_t h) { return static_cast<std::uint32_t>(h >> 32); }

/// A hash-derived value in [0,1) with 32 bits, for the jitter inside a stratum.
double hashUnit(std::uint32_t i, std::uint32_t seed) { return fixedToUnit(hash32(hash32(i ^ seed) + seed)); }

}  // namespace

// ---------------------------------------------------------------------------------------------------
// independent

double IndependentSampler::value1D(std::uint64_t key, std::uint32_t index, std::uint32_t, std::uint64_t dim) const {
    Rng rng(hashWords(index, dim), key);
    return rng.uniform();
}

Point2 IndependentSampler::value2D(std::uint64_t key, std::uint32_t index, std::uint32_t, std::uint64_t dim) const {
    Rng rng(hashWords(index, dim), key);
    return rng.uniform2();
}

// ---------------------------------------------------------------------------------------------------
// stratified: Kensler's correlated multi-jittered sampling, one pattern per (pixel, dimension)

double StratifiedSampler::value1D(std::uint64_t key, std::uint32_t index, std::uint32_t count, std::uint64_t dim) const {
    const std::uint64_t h = hashWords(key, dim, 1);
    const std::uint32_t n = std::max(1u, count), p = low32(h);
    const std::uint32_t s = permuteAny(index % n, n, high32(h));
    return std::min(kOneBelow, (s + hashUnit(s, p * 0x967a889bu)) / n);
}

Point2 StratifiedSampler::value2D(std::uint64_t key, std::uint32_t index, std::uint32_t count, std::uint64_t dim) const {
    // x = (sx + (sy + jx)/n)/m: column sx of m, and inside it row sy of n; y = (s + jy)/N: stratum s of N.
    const std::uint64_t h = hashWords(key, dim, 2);
    const std::uint32_t N = std::max(1u, count), p = low32(h), q = high32(h);
    const std::uint32_t m = std::max(1u, static_cast<std::uint32_t>(std::sqrt(static_cast<double>(N))));
    const std::uint32_t n = (N + m - 1) / m;
    const std::uint32_t s = permuteAny(index % N, N, q);
    const std::uint32_t sx = permuteAny(s % m, m, hash32(q ^ 0x68bc21ebu));
    const std::uint32_t sy = permuteAny(s / m, n, hash32(q ^ 0x02e5be93u));
    const double jx = hashUnit(s, p * 0x967a889bu), jy = hashUnit(s, p * 0x368cc8b7u);
    return {std::min(kOneBelow, (sx + (sy + jx) / n) / m), std::min(kOneBelow, (s + jy) / N)};
}

// ---------------------------------------------------------------------------------------------------
// sobol: padded, Owen-scrambled (0,2)-sequence. One 64-bit hash of (pixel key, dimension) gives the
// scramble seeds; a 32-bit hash of those the permutation's.

Vec3 SobolSampler::value3D(std::uint64_t key, std::uint32_t index, std::uint32_t count, std::uint64_t dim) const {
    const std::uint64_t h = mixSeed(key, 2 * dim);
    const std::uint32_t j = permuteSamples(index, count, pairPermutationSeed(h));
    const std::uint32_t s2 = low32(mixSeed(key, 2 * (dim + 2)));
    return {fixedToUnit(owenScrambledSobol0(j, low32(h))), fixedToUnit(owenScrambledSobol1(j, high32(h))),
            fixedToUnit(owenScramble(kSobolDimension2(j), s2))};
}

Point2 SobolSampler::value2DJoint(std::uint64_t key, std::uint32_t index, std::uint32_t count, std::uint64_t dim,
                                  std::uint64_t partner) const {
    const std::uint32_t j = permuteSamples(index, count, pairPermutationSeed(mixSeed(key, 2 * partner)));
    const std::uint64_t h = mixSeed(key, 2 * dim);
    return {fixedToUnit(owenScramble(kSobolDimension2(j), low32(h))), fixedToUnit(owenScramble(kSobolDimension3(j), high32(h)))};
}

// ---------------------------------------------------------------------------------------------------

std::uint32_t SampleStream::patternEntry(std::uint32_t entries) {
    const std::uint32_t round = patternRound(entries);
    const std::uint32_t key = low32(hashWords(key_, dim_++, round));
    return permuteAny(index_ % entries, entries, key);
}

}  // namespace symphong
