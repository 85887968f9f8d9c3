// sampling/sobol_lanes.h — the sobol sampler's values for many camera samples at once: one dimension (or
// pair) of n streams, each its own pixel key and sample index, of one pattern size. The same values as
// SobolSampler::singleValue and pairValue bit for bit; where the processor has AVX-512 (F, DQ, BW, VL) and
// GFNI, eight streams a step in vector lanes (the pixel hash's 64-bit products in vpmullq, the
// permutation's GF(2^k) tables and Sobol' dimension 1's by gathers, the bit reversals by GFNI's affine
// byte map), checked at run time; otherwise, or for a pattern size the lanes do not take (not a power of
// two, or above 2^10), the scalar functions one stream at a time. The wavefront tracer asks for a depth's
// values of all its live paths here (render/wavefront.cpp); docs/performance.md has what it saves.
#pragma once

#include <cstddef>
#include <cstdint>

namespace symphong {

/// us[i], vs[i] = SobolSampler::pairValue(keys[i], indices[i], count, dim), i < n.
void sobolPairValues(const std::uint64_t* keys, const std::uint32_t* indices, std::uint32_t count, std::uint64_t dim, std::size_t n,
                     double* us, double* vs);
/// out[i] = SobolSampler::singleValue(keys[i], indices[i], count, dim), i < n.
void sobolSingleValues(const std::uint64_t* keys, const std::uint32_t* indices, std::uint32_t count, std::uint64_t dim, std::size_t n,
                       double* out);
/// Whether the calls above run in vector lanes on this processor (AVX-512 F/DQ/BW/VL and GFNI).
bool sobolLanesAvailable();

namespace detail {
/// The two forms, for tests: one stream at a time, and the lanes (only where sobolLanesAvailable(); any
/// pattern size, falling back to the scalar form where the lanes do not take it).
void sobolPairValuesScalar(const std::uint64_t* keys, const std::uint32_t* indices, std::uint32_t count, std::uint64_t dim, std::size_t n,
                           double* us, double* vs);
void sobolSingleValuesScalar(const std::uint64_t* keys, const std::uint32_t* indices, std::uint32_t count, std::uint64_t dim, std::size_t n,
                             double* out);
void sobolPairValuesLanes(const std::uint64_t* keys, const std::uint32_t* indices, std::uint32_t count, std::uint64_t dim, std::size_t n,
                          double* us, double* vs);
void sobolSingleValuesLanes(const std::uint64_t* keys, const std::uint32_t* indices, std::uint32_t count, std::uint64_t dim, std::size_t n,
                            double* out);
}  // namespace detail

}  // namespace symphong
