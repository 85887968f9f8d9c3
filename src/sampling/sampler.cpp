#include "sampling/sampler.h"

#include "sampling/lowdiscrepancy.h"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

namespace symphong {

namespace {

/// The largest double below 1: values are clamped to it so a warp never sees u = 1.
constexpr double kOneMinusEpsilon = 0x1.fffffffffffffp-1;

std::uint32_t low32(std::uint64_t h) { return static_cast<std::uint32_t>(h); }
std::uint32_t high32(std::uint64_t h) { return static_cast<std::uint32_t>(h >> 32); }

/// A hash-derived value in [0,1) with 32 bits, for the jitter inside a stratum.
double hashUnit(std::uint32_t i, std::uint32_t seed) { return fixedToUnit(hash32(hash32(i ^ seed) + seed)); }

}  // namespace

// ---------------------------------------------------------------------------------------------------
// independent

double IndependentSampler::sample1D(std::uint64_t pixel, std::uint32_t index, std::uint64_t dim) const {
    Rng rng(hashWords(seed(), pixel, index), pixel);
    rng.advance(2 * dim);
    return rng.uniform();
}

Point2 IndependentSampler::sample2D(std::uint64_t pixel, std::uint32_t index, std::uint64_t dim) const {
    Rng rng(hashWords(seed(), pixel, index), pixel);
    rng.advance(2 * dim);
    return rng.uniform2();  // the same values as sample1D(dim) and sample1D(dim + 1)
}

// ---------------------------------------------------------------------------------------------------
// stratified: Kensler's correlated multi-jittered sampling, one pattern per (pixel, dimension)

double StratifiedSampler::sample1D(std::uint64_t pixel, std::uint32_t index, std::uint64_t dim) const {
    const std::uint32_t n = samplesPerPixel(), p = low32(hashWords(seed(), pixel, dim, 1));
    const std::uint32_t s = permuteIndex(index % n, n, p);
    return std::min(kOneMinusEpsilon, (s + hashUnit(s, p * 0x967a889bu)) / n);
}

Point2 StratifiedSampler::sample2D(std::uint64_t pixel, std::uint32_t index, std::uint64_t dim) const {
    // x = (sx + (sy + jx)/n)/m: column sx of m, and inside it row sy of n; y = (s + jy)/N: stratum s of N.
    const std::uint32_t N = samplesPerPixel(), p = low32(hashWords(seed(), pixel, dim, 2));
    const std::uint32_t m = std::max(1u, static_cast<std::uint32_t>(std::sqrt(static_cast<double>(N))));
    const std::uint32_t n = (N + m - 1) / m;
    const std::uint32_t s = permuteIndex(index % N, N, p * 0x51633e2du);
    const std::uint32_t sx = permuteIndex(s % m, m, p * 0x68bc21ebu);
    const std::uint32_t sy = permuteIndex(s / m, n, p * 0x02e5be93u);
    const double jx = hashUnit(s, p * 0x967a889bu), jy = hashUnit(s, p * 0x368cc8b7u);
    return {std::min(kOneMinusEpsilon, (sx + (sy + jx) / n) / m), std::min(kOneMinusEpsilon, (s + jy) / N)};
}

// ---------------------------------------------------------------------------------------------------
// sobol: padded, Owen-scrambled (0,2)-sequence

double SobolSampler::sample1D(std::uint64_t pixel, std::uint32_t index, std::uint64_t dim) const {
    const std::uint64_t h = hashWords(seed(), pixel, dim, 1);
    const std::uint32_t j = permuteIndex(index, samplesPerPixel(), high32(h));
    return fixedToUnit(owenScramble(sobolDimension0(j), low32(h)));
}

Point2 SobolSampler::sample2D(std::uint64_t pixel, std::uint32_t index, std::uint64_t dim) const {
    const std::uint64_t h = hashWords(seed(), pixel, dim, 2), h2 = hashWords(h, 3);
    const std::uint32_t j = permuteIndex(index, samplesPerPixel(), low32(h2));
    return {fixedToUnit(owenScramble(sobolDimension0(j), low32(h))), fixedToUnit(owenScramble(sobolDimension1(j), high32(h)))};
}

// ---------------------------------------------------------------------------------------------------

const std::vector<std::string>& samplerNames() {
    static const std::vector<std::string> names = {"independent", "stratified", "sobol"};
    return names;
}

std::string samplerHelp() {
    return "independent - independent uniform numbers (PCG32 streams)\n"
           "stratified  - jittered strata (correlated multi-jittered) in every dimension pair, any spp\n"
           "sobol       - Owen-scrambled Sobol' (0,2)-sequence in every dimension pair (the default)";
}

std::unique_ptr<Sampler> makeSampler(std::string_view name, std::uint32_t samplesPerPixel, std::uint64_t seed) {
    if (name == "independent") return std::make_unique<IndependentSampler>(samplesPerPixel, seed);
    if (name == "stratified") return std::make_unique<StratifiedSampler>(samplesPerPixel, seed);
    if (name == "sobol") return std::make_unique<SobolSampler>(samplesPerPixel, seed);
    throw std::invalid_argument(fmt::format("unknown sampler '{}' (valid: {})", name, fmt::join(samplerNames(), ", ")));
}

}  // namespace symphong
