// sampling/lowdiscrepancy.h — the building blocks of the low-discrepancy samplers: the first two
// Sobol' dimensions (together a (0,2)-sequence in base 2), Owen scrambling by hashing, hash-based
// permutations, and the integer hashes that seed them. Small pure functions on 32-bit fixed-point
// values (x = v / 2^32); sampling/sampler.h turns them into samplers. Models: pbrt-v4's
// util/lowdiscrepancy.h, Burley 2020 ("Practical Hash-based Owen Scrambling", JCGT 9(4)), Kensler 2013
// ("Correlated Multi-Jittered Sampling", Pixar TM 13-01).
#pragma once

#include "sampling/rng.h"

#include <bit>
#include <cstdint>

namespace symphong {

/// Bit reversal of a 32-bit word: bit k goes to bit 31 - k.
constexpr std::uint32_t reverseBits32(std::uint32_t v) {
    v = ((v >> 1) & 0x55555555u) | ((v & 0x55555555u) << 1);
    v = ((v >> 2) & 0x33333333u) | ((v & 0x33333333u) << 2);
    v = ((v >> 4) & 0x0F0F0F0Fu) | ((v & 0x0F0F0F0Fu) << 4);
    v = ((v >> 8) & 0x00FF00FFu) | ((v & 0x00FF00FFu) << 8);
    return (v >> 16) | (v << 16);
}

/// Sobol' dimension 0, the van der Corput sequence in base 2: x_i = sum_k i_k 2^-(k+1), i.e. the
/// generator matrix is the identity and the value is the index's bits mirrored about the binary point.
constexpr std::uint32_t sobolDimension0(std::uint32_t index) { return reverseBits32(index); }

/// Sobol' dimension 1 by the definition: its generator matrix is Pascal's triangle mod 2: column k
/// (the bit of index bit k, most significant output bit first) has bit j set when C(j, k) is odd
/// (j >= k). As 32-bit words, column k is the Sierpinski row v_k = v_{k-1} ^ (v_{k-1} >> 1),
/// v_0 = 2^31, and x_i = XOR over the set bits k of i of v_k. Together with sobolDimension0 it is a
/// (0,2)-sequence: every block of 2^m consecutive points starting at a multiple of 2^m has exactly one
/// point in each elementary interval [a/2^p, (a+1)/2^p) x [b/2^q, (b+1)/2^q), p + q = m.
constexpr std::uint32_t sobolDimension1Loop(std::uint32_t index) {
    std::uint32_t x = 0, v = 0x80000000u;
    for (; index != 0; index >>= 1, v ^= v >> 1)
        if (index & 1u) x ^= v;
    return x;
}

namespace detail {
/// sobolDimension1 of every byte value at byte position b: the XOR of the columns of that byte's bits;
/// and the same bit-reversed.
struct SobolDimension1Tables {
    std::uint32_t t[4][256] = {}, reversed[4][256] = {};
    constexpr SobolDimension1Tables() {
        for (int b = 0; b < 4; ++b)
            for (std::uint32_t i = 0; i < 256; ++i) {
                t[b][i] = sobolDimension1Loop(i << (8 * b));
                reversed[b][i] = reverseBits32(t[b][i]);
            }
    }
};
inline constexpr SobolDimension1Tables kSobolDimension1Tables{};

/// Laine and Karras's nested-scramble hash on a bit-reversed value (the core of owenScramble).
constexpr std::uint32_t laineKarras(std::uint32_t v, std::uint32_t seed) {
    v ^= v * 0x3d20adeau;
    v += seed;
    v *= (seed >> 16) | 1u;
    v ^= v * 0x05526c56u;
    v ^= v * 0x53a22864u;
    return v;
}
}  // namespace detail

/// Sobol' dimension 1 (see sobolDimension1Loop) by four table look-ups, one per byte of the index: the
/// map is linear over GF(2), so the bytes' contributions XOR. No data-dependent branches (the
/// scrambled sample order makes the loop's branches unpredictable).
constexpr std::uint32_t sobolDimension1(std::uint32_t index) {
    const auto& t = detail::kSobolDimension1Tables.t;
    return t[0][index & 0xFFu] ^ t[1][(index >> 8) & 0xFFu] ^ t[2][(index >> 16) & 0xFFu] ^ t[3][index >> 24];
}

/// 32-bit integer hash with full avalanche (Wellons' "lowbias32").
constexpr std::uint32_t hash32(std::uint32_t x) {
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    x ^= x >> 16;
    return x;
}

/// Hash of several 64-bit words (SplitMix64 finaliser applied along the chain); different argument
/// lists give independent-looking 64-bit values.
constexpr std::uint64_t hashWords(std::uint64_t a, std::uint64_t b) { return mixSeed(a, b); }
constexpr std::uint64_t hashWords(std::uint64_t a, std::uint64_t b, std::uint64_t c) { return mixSeed(mixSeed(a, b), c); }
constexpr std::uint64_t hashWords(std::uint64_t a, std::uint64_t b, std::uint64_t c, std::uint64_t d) {
    return mixSeed(mixSeed(mixSeed(a, b), c), d);
}

/// Owen scrambling (nested uniform scrambling) of a 32-bit fixed-point value, by hashing: digit k
/// (k = 0 the most significant) is flipped by a pseudo-random function of the seed and of the digits
/// above it, and of nothing else. Implemented as Laine and Karras's trick with Vegdahl's constants
/// (as in Burley 2020 and pbrt-v4's FastOwenScrambler): on the bit-reversed value, v ^= v * even and
/// v *= odd only carry information from lower to higher bits, i.e. from more to less significant
/// digits of x, so the map is a nested scramble; it keeps (t,m,s)-nets nets.
constexpr std::uint32_t owenScramble(std::uint32_t v, std::uint32_t seed) {
    return reverseBits32(detail::laineKarras(reverseBits32(v), seed));
}

/// owenScramble(sobolDimension0(index), seed) with the two bit reversals that cancel left out.
constexpr std::uint32_t owenScrambledSobol0(std::uint32_t index, std::uint32_t seed) {
    return reverseBits32(detail::laineKarras(index, seed));
}

/// owenScramble(sobolDimension1(index), seed), from bit-reversed tables (one reversal saved).
constexpr std::uint32_t owenScrambledSobol1(std::uint32_t index, std::uint32_t seed) {
    const auto& r = detail::kSobolDimension1Tables.reversed;
    const std::uint32_t rev = r[0][index & 0xFFu] ^ r[1][(index >> 8) & 0xFFu] ^ r[2][(index >> 16) & 0xFFu] ^ r[3][index >> 24];
    return reverseBits32(detail::laineKarras(rev, seed));
}

/// Owen scrambling digit by digit (slow, exact form of the definition): digit k is flipped when a hash of
/// (seed, the k digits above it, k) is odd. A reference for tests of owenScramble's properties.
constexpr std::uint32_t owenScrambleExact(std::uint32_t v, std::uint32_t seed) {
    std::uint32_t out = v;
    for (int k = 0; k < 32; ++k) {
        const std::uint32_t above = k == 0 ? 0u : (v >> (32 - k));
        if (hash32(hash32(seed ^ above) + static_cast<std::uint32_t>(k) * 0x9E3779B9u) & 1u) out ^= 0x80000000u >> k;
    }
    return out;
}

/// A fixed-point value as a double in [0, 1): v / 2^32.
constexpr double fixedToUnit(std::uint32_t v) { return static_cast<double>(v) * (1.0 / 4294967296.0); }

/// A pseudo-random permutation of {0, ..., n-1} applied to i (Kensler 2013, "permute"): a hash-based
/// bijection on the next power of two, cycle-walked until it lands below n. Different seeds give
/// (nearly) independent permutations.
constexpr std::uint32_t permuteIndex(std::uint32_t i, std::uint32_t n, std::uint32_t seed) {
    if (n <= 1) return 0;
    std::uint32_t w = n - 1;
    w |= w >> 1;
    w |= w >> 2;
    w |= w >> 4;
    w |= w >> 8;
    w |= w >> 16;
    do {
        i ^= seed;
        i *= 0xe170893du;
        i ^= seed >> 16;
        i ^= (i & w) >> 4;
        i ^= seed >> 8;
        i *= 0x0929eb3fu;
        i ^= seed >> 23;
        i ^= (i & w) >> 1;
        i *= 1u | seed >> 27;
        i *= 0x6935fa69u;
        i ^= (i & w) >> 11;
        i *= 0x74dcb303u;
        i ^= (i & w) >> 2;
        i *= 0x9e501cc3u;
        i ^= (i & w) >> 2;
        i *= 0xc860a3dfu;
        i &= w;
        i ^= i >> 5;
    } while (i >= n);
    return (i + seed) % n;
}

/// A pseudo-random permutation of {0, ..., n-1} for n a power of two, 2^k (cheaper than permuteIndex,
/// which it equals in purpose): three rounds of xor with the seed, multiplication by an odd constant
/// and a right xorshift, each a bijection of k-bit words; the multiplications carry low bits up and the
/// xorshifts high bits down, so every output bit depends nonlinearly on every input bit.
constexpr std::uint32_t permutePowerOfTwo(std::uint32_t i, std::uint32_t k, std::uint32_t seed) {
    if (k == 0) return 0;
    const std::uint32_t mask = k >= 32 ? 0xFFFFFFFFu : (1u << k) - 1u, shift = k / 2 + 1;
    i = ((i ^ seed) * 0xe170893du) & mask;
    i ^= i >> shift;
    i = ((i ^ (seed >> 8)) * (0x0929eb3fu | (seed >> 27) << 1)) & mask;
    i ^= i >> shift;
    i = ((i ^ (seed >> 16)) * 0x6935fa69u) & mask;
    i ^= i >> shift;
    return i;
}

/// permutePowerOfTwo when n is a power of two, permuteIndex otherwise.
constexpr std::uint32_t permuteAny(std::uint32_t i, std::uint32_t n, std::uint32_t seed) {
    if ((n & (n - 1)) == 0) return permutePowerOfTwo(i, static_cast<std::uint32_t>(std::countr_zero(n)), seed);
    return permuteIndex(i, n, seed);
}

}  // namespace symphong
