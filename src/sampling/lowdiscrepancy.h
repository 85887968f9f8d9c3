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

/// Sobol' dimension 1 by the definition: its generator matrix is the upper-triangular Pascal matrix
/// mod 2: column k (the output of index bit k; output digit j counted from the most significant) has
/// digit j set when C(k, j) is odd (j <= k). As 32-bit words, column k is the Sierpinski row v_k = v_{k-1} ^ (v_{k-1} >> 1),
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

/// The 32 generator-matrix columns of a Sobol' dimension from its primitive polynomial (degree s,
/// inner coefficients a, a_1 the most significant of s-1 bits) and initial numbers m_1..m_s (Joe and Kuo
/// 2008, "Constructing Sobol sequences with better two-dimensional projections"): V_k = m_k 2^(32-k) for
/// k <= s, then V_k = V_{k-s} ^ (V_{k-s} >> s) ^ XOR_{j=1..s-1} a_j V_{k-j}. Column k - 1 is the output
/// of index bit k - 1.
struct SobolMatrix {
    std::uint32_t column[32] = {};
    constexpr SobolMatrix(int s, std::uint32_t a, const std::uint32_t* m) {
        for (int k = 1; k <= 32; ++k) {
            std::uint32_t v;
            if (k <= s) {
                v = m[k - 1] << (32 - k);
            } else {
                v = column[k - s - 1] ^ (column[k - s - 1] >> s);
                for (int j = 1; j < s; ++j)
                    if ((a >> (s - 1 - j)) & 1u) v ^= column[k - j - 1];
            }
            column[k - 1] = v;
        }
        for (int b = 0; b < 4; ++b)
            for (std::uint32_t i = 0; i < 256; ++i) byteTable[b][i] = byDefinition(i << (8 * b));
    }
    std::uint32_t byteTable[4][256] = {};  ///< XOR of the columns of each byte value's bits, per byte position
    /// x_i = XOR of the columns of the set bits of i, by definition (a reference for tests).
    constexpr std::uint32_t byDefinition(std::uint32_t index) const {
        std::uint32_t x = 0;
        for (int k = 0; index != 0; ++k, index >>= 1)
            if (index & 1u) x ^= column[k];
        return x;
    }
    /// The same by four table look-ups (the map is linear over GF(2), so the bytes' parts XOR).
    constexpr std::uint32_t operator()(std::uint32_t index) const {
        return byteTable[0][index & 0xFFu] ^ byteTable[1][(index >> 8) & 0xFFu] ^ byteTable[2][(index >> 16) & 0xFFu] ^
               byteTable[3][index >> 24];
    }
};

namespace detail {
inline constexpr std::uint32_t kSobolM2[2] = {1, 3};     // Joe-Kuo dimension 3: x^2 + x + 1, m = 1, 3
inline constexpr std::uint32_t kSobolM3[3] = {1, 3, 1};  // Joe-Kuo dimension 4: x^3 + x + 1, m = 1, 3, 1
}  // namespace detail
/// Sobol' dimensions 2 and 3 (0-based; Joe and Kuo's dimensions 3 and 4): with dimensions 0 and 1 the
/// first four dimensions of the sequence, for a 4D pattern (the pixel position and the first bounce).
inline constexpr SobolMatrix kSobolDimension2{2, 1, detail::kSobolM2};
inline constexpr SobolMatrix kSobolDimension3{3, 1, detail::kSobolM3};

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

/// Blocks of a Sobol' (0,2)-sequence: the pixel's count = 2^k samples each own the aligned block of
/// kBlockSize consecutive points [8 a, 8 a + 8) of a pattern of 8 x 2^k points (a: the sample's permuted
/// index), and continuation j < 8 of sample a is point
///   8 a + (f_k(a) XOR j),
/// with f_k a GF(2)-linear map of a's bits into 3 bits. A sample's first n = 2^p continuations are an
/// aligned sub-block of its block (XOR with j < n touches only the low p bits), so a (0,p,2)-net among
/// themselves; and continuation j of all 2^k samples is a (0,k,2)-net: for j = 0 because f_k feeds a's top
/// three bits into the three most significant digits of the first coordinate (the rows below were found
/// by exhaustive search against sobolDimension0/1, tests/test_samplers.cpp checks them for k = 0..14; f_k
/// repeats with period 4 in k >= 3, as the Pascal matrix mod 2 does), and for every other j because
/// XOR with j adds the fixed vector point(j) to every point of a digital net (a digital shift, which keeps
/// a net a net). Owen scrambling keeps both properties. A sample's own continuations are thus stratified
/// (the smooth part of their integrand averages out faster than 1/n) while any one continuation across
/// the pixel is as stratified as an unsplit render's direction. For a count that is not a power of two, k
/// is the next power's: every property above holds only for the whole 2^k.
inline constexpr std::uint32_t kBlockSize = 8;
namespace detail {
/// Rows of f_k (bit b of f_k(a) is the parity of row_b AND a): k = 1, 2 as masks of a's k bits; k >= 3 as
/// masks of a's top three bits (bit 0 = a's bit k - 3), by k mod 4.
inline constexpr std::uint32_t kBlockRowsSmall[3][3] = {{0, 0, 0}, {1, 0, 1}, {1, 2, 2}};
inline constexpr std::uint32_t kBlockRowsTop[4][3] = {{2, 5, 6}, {1, 2, 5}, {1, 3, 6}, {1, 6, 4}};
constexpr std::uint32_t parity(std::uint32_t v) { return static_cast<std::uint32_t>(std::popcount(v)) & 1u; }
}  // namespace detail
/// f_k(a) XOR j + 8 a: continuation j (< kBlockSize) of the sample with permuted index a < 2^k.
constexpr std::uint32_t blockPoint(std::uint32_t a, std::uint32_t k, std::uint32_t j) {
    const std::uint32_t* rows = k < 3 ? detail::kBlockRowsSmall[k] : detail::kBlockRowsTop[k % 4];
    const std::uint32_t bits = k < 3 ? a : a >> (k - 3);
    const std::uint32_t f = detail::parity(rows[0] & bits) | detail::parity(rows[1] & bits) << 1 | detail::parity(rows[2] & bits) << 2;
    return a * kBlockSize + (f ^ j);
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
    return (i + seed % n) % n;  // seed % n first: i + seed could wrap around 2^32 and collide
}

namespace detail {
/// A primitive (so irreducible) polynomial of degree k over GF(2), k = 0..20, with its x^k bit.
inline constexpr std::uint32_t kIrreducible[21] = {0x1,    0x3,    0x7,     0xB,     0x13,    0x25,    0x43,
                                                   0x83,   0x11D,  0x211,   0x409,   0x805,   0x1053,  0x201B,
                                                   0x4443, 0x8003, 0x1100B, 0x20009, 0x40081, 0x80027, 0x100009};

/// a * b in GF(2^k) (carry-less product reduced by kIrreducible[k]); a, b < 2^k. Branch-free, k steps:
/// the bits of b are random, so branches on them would be mispredicted half the time.
constexpr std::uint32_t gfMultiply(std::uint32_t a, std::uint32_t b, std::uint32_t k) {
    const std::uint32_t mask = (1u << k) - 1u, poly = kIrreducible[k] & mask;
    std::uint32_t r = 0;
    for (std::uint32_t t = 0; t < k; ++t, b >>= 1) {
        r ^= a & (0u - (b & 1u));
        const std::uint32_t carry = (a >> (k - 1)) & 1u;
        a = ((a << 1) & mask) ^ (poly & (0u - carry));
    }
    return r;
}
/// x^e in GF(2^k) by square-and-multiply.
constexpr std::uint32_t gfPowerOfX(std::uint32_t e, std::uint32_t k) {
    std::uint32_t result = 1, base = k == 1 ? 1u : 2u;
    for (; e != 0; e >>= 1) {
        if (e & 1u) result = gfMultiply(result, base, k);
        base = gfMultiply(base, base, k);
    }
    return result;
}

/// Discrete logarithm and exponential tables of GF(2^k), k = 1..10, base x (the polynomials are
/// primitive, so x generates the multiplicative group of 2^k - 1 elements): a * b = exp[log a + log b].
/// exp is stored twice over so that a sum of two logarithms needs no reduction.
struct GfTables {
    static constexpr std::uint32_t kMaxK = 10;
    std::uint16_t exp[kMaxK + 1][2 << kMaxK] = {}, log[kMaxK + 1][1 << kMaxK] = {};
    constexpr GfTables() {
        for (std::uint32_t k = 1; k <= kMaxK; ++k) {
            const std::uint32_t order = (1u << k) - 1u;
            std::uint32_t v = 1;
            for (std::uint32_t e = 0; e < order; ++e) {
                exp[k][e] = exp[k][e + order] = static_cast<std::uint16_t>(v);
                log[k][v] = static_cast<std::uint16_t>(e);
                v = gfMultiply(v, k == 1 ? 1u : 2u, k);
            }
        }
    }
};
inline constexpr GfTables kGfTables{};
}  // namespace detail

/// A pseudo-random permutation of {0, ..., n-1} for n = 2^k, 1 <= k <= 20: the affine map
///   i -> a i + b  in the field GF(2^k),  a != 0 and b taken from the seed (a well-mixed hash).
/// These maps form a sharply 2-transitive group, so for a random seed every ordered pair of distinct
/// indices goes to every ordered pair of distinct values with the same probability: two dimensions
/// permuted this way are matched like two independent uniform permutations in every pairwise statistic
/// (correlations, the offsets between images). Cost: k shift-and-xor steps.
constexpr std::uint32_t permutePowerOfTwo(std::uint32_t i, std::uint32_t k, std::uint32_t seed) {
    if (k == 0) return 0;
    // The seed is a hash already: a uniform on 1..2^k-1 from its high bits (Lemire's multiply-shift, no
    // division), b on 0..2^k-1 from the top bits of a multiplicative hash of all its bits.
    const std::uint32_t mask = (1u << k) - 1u;
    const std::uint32_t logA = static_cast<std::uint32_t>((static_cast<std::uint64_t>(seed) * mask) >> 32);  // a = x^logA
    const std::uint32_t b = (seed * 0x9E3779B9u) >> (32 - k);
    i &= mask;
    if (k <= detail::GfTables::kMaxK) {  // small k (spp up to 1024): two table look-ups
        const auto& t = detail::kGfTables;
        return (i == 0 ? 0u : t.exp[k][t.log[k][i] + logA]) ^ b;
    }
    return detail::gfMultiply(i, detail::gfPowerOfX(logA, k), k) ^ b;
}

/// A pseudo-random permutation of {0, ..., n-1}: for n = 2^k <= 2^20 permutePowerOfTwo (exactly
/// 2-transitive over seeds); otherwise permutePowerOfTwo on the next power of two, cycle-walked (applied
/// again while the value is n or more: still a bijection of {0..n-1}), followed by Kensler's
/// permuteIndex with an independent seed, since cycle walking alone leaves the offsets between images
/// visibly non-uniform (and so does Kensler's hash alone, at small n).
constexpr std::uint32_t permuteAny(std::uint32_t i, std::uint32_t n, std::uint32_t seed) {
    if (n <= 1) return 0;
    if (n > (1u << 20)) return permuteIndex(permuteIndex(i, n, seed), n, hash32(seed ^ 0x68bc21ebu));
    const std::uint32_t k = static_cast<std::uint32_t>(std::bit_width(n - 1));
    std::uint32_t j = permutePowerOfTwo(i, k, seed);
    if (n == (1u << k)) return j;
    while (j >= n) j = permutePowerOfTwo(j, k, seed);
    return permuteIndex(j, n, hash32(seed ^ 0x68bc21ebu));
}

/// permuteAny(i, n, seed), the same values, with its common case inline: n a power of two up to 2^10 (a
/// pixel's spp, or spp x k for --split k, up to 1024) is permutePowerOfTwo's two table look-ups.
constexpr std::uint32_t permuteSamples(std::uint32_t i, std::uint32_t n, std::uint32_t seed) {
    if (n > 1 && n <= (1u << detail::GfTables::kMaxK) && (n & (n - 1)) == 0)
        return permutePowerOfTwo(i, static_cast<std::uint32_t>(std::bit_width(n - 1)), seed);
    return permuteAny(i, n, seed);
}

}  // namespace symphong
