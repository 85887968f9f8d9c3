// Samplers: (0,2)-net property of the scrambled Sobol' pairs and of their building blocks, strata of
// the Sobol' 1D dimensions and of the stratified sampler, uniformity of every dimension, independence
// of different dimensions (across pixels and within a pixel), determinism and seeds, SampleStream's
// dimension bookkeeping, and permuteIndex. Every statistical test uses a fixed seed and a tolerance
// taken from the statistic's own distribution: a chi-square p-value against alpha = 0.01, Sidak-corrected
// over the chi-square runs of the test, or 4 standard errors. Each checker is also shown to reject a
// deliberately broken input, so that it can fail.
#include "sampling/alias_table.h"
#include "sampling/lowdiscrepancy.h"
#include "sampling/sampler.h"
#include "sampling/sobol_lanes.h"

#include "stats.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <map>
#include <memory>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

using namespace symphong;
using symphong::test::gammaQ;
using symphong::test::meanAndError;

namespace {

// ---------------------------------------------------------------------------------------------------
// helpers

constexpr double kAlpha = 0.01;
/// Per-run level for `runs` chi-square tests in one TEST, so that the TEST's false-alarm rate is kAlpha.
double sidak(int runs) { return 1.0 - std::pow(1.0 - kAlpha, 1.0 / runs); }

struct Chi2 {
    double statistic = 0;
    int dof = 0;
    double p = 1;
    std::string str() const {
        return "chi2 = " + std::to_string(statistic) + ", dof = " + std::to_string(dof) + ", p = " + std::to_string(p);
    }
};

/// Pearson chi-square of counts against equal expected counts (a fully specified null: dof = cells - 1).
Chi2 chiSquareEqual(const std::vector<double>& counts) {
    double total = 0;
    for (double c : counts) total += c;
    const double expected = total / static_cast<double>(counts.size());
    Chi2 r;
    for (double c : counts) r.statistic += (c - expected) * (c - expected) / expected;
    r.dof = static_cast<int>(counts.size()) - 1;
    r.p = gammaQ(0.5 * r.dof, 0.5 * r.statistic);
    return r;
}

int binOf(double x, int bins) { return std::min(bins - 1, static_cast<int>(x * bins)); }

/// Chi-square of values against the uniform density on [0,1) with `bins` equal bins.
Chi2 chiSquareUniform(const std::vector<double>& xs, int bins) {
    std::vector<double> counts(bins, 0.0);
    for (double x : xs) counts[binOf(x, bins)] += 1;
    return chiSquareEqual(counts);
}

/// Chi-square of pairs against the uniform density on [0,1)^2 (independent uniform coordinates),
/// bins x bins cells.
Chi2 chiSquareUniform2D(const std::vector<double>& xs, const std::vector<double>& ys, int bins) {
    std::vector<double> counts(static_cast<std::size_t>(bins) * bins, 0.0);
    for (std::size_t k = 0; k < xs.size(); ++k) counts[binOf(xs[k], bins) * bins + binOf(ys[k], bins)] += 1;
    return chiSquareEqual(counts);
}

double correlation(const std::vector<double>& xs, const std::vector<double>& ys) {
    const double n = static_cast<double>(xs.size());
    double mx = 0, my = 0;
    for (std::size_t k = 0; k < xs.size(); ++k) mx += xs[k], my += ys[k];
    mx /= n;
    my /= n;
    double sxy = 0, sxx = 0, syy = 0;
    for (std::size_t k = 0; k < xs.size(); ++k) {
        sxy += (xs[k] - mx) * (ys[k] - my);
        sxx += (xs[k] - mx) * (xs[k] - mx);
        syy += (ys[k] - my) * (ys[k] - my);
    }
    return sxy / std::sqrt(sxx * syy);
}

/// A value of a low-discrepancy sampler as its exact 32-bit fixed point (x = v / 2^32); fails the test
/// if x is not such a value.
std::uint32_t toFixed(double x) {
    const double scaled = x * 4294967296.0;
    EXPECT_TRUE(x >= 0 && x < 1 && scaled == std::floor(scaled)) << "not a multiple of 2^-32 in [0,1): " << x;
    return static_cast<std::uint32_t>(scaled);
}

using FixedPoint = std::array<std::uint32_t, 2>;

/// Equidistribution in elementary intervals: for a point set of N = c 2^t points (t = the number of
/// trailing zero bits of N), every elementary interval [a/2^p, (a+1)/2^p) x [b/2^q, (b+1)/2^q) with
/// p + q = t, for every shape p = 0..t, must hold exactly c points. For N = 2^k this is "the set is a
/// (0,k,2)-net in base 2"; for other N it is what the first N points of a (0,2)-sequence satisfy (they
/// are a union of aligned blocks of 2^t or more points, each a net). Returns "" or the first failure.
std::string netFailure(const std::vector<FixedPoint>& pts) {
    const std::size_t n = pts.size();
    const int t = std::countr_zero(n);
    const std::size_t cells = std::size_t{1} << t, per = n >> t;
    std::vector<std::size_t> count(cells);
    for (int p = 0; p <= t; ++p) {
        const int q = t - p;
        std::fill(count.begin(), count.end(), 0);
        for (const FixedPoint& pt : pts) {
            const std::uint64_t a = std::uint64_t{pt[0]} >> (32 - p), b = std::uint64_t{pt[1]} >> (32 - q);
            ++count[(a << q) | b];
        }
        for (std::size_t c = 0; c < cells; ++c)
            if (count[c] != per)
                return "N = " + std::to_string(n) + ", shape 2^-" + std::to_string(p) + " x 2^-" + std::to_string(q) + ", cell (" +
                       std::to_string(c >> q) + ", " + std::to_string(c & ((std::size_t{1} << q) - 1)) + ") holds " +
                       std::to_string(count[c]) + " points instead of " + std::to_string(per);
    }
    return "";
}

/// 1D strata: N = c 2^t values (32-bit fixed point), each [j/2^t, (j+1)/2^t) must hold exactly c.
std::string strataFailure(const std::vector<std::uint32_t>& xs) {
    const std::size_t n = xs.size();
    const int t = std::countr_zero(n);
    std::vector<std::size_t> count(std::size_t{1} << t);
    for (std::uint32_t x : xs) ++count[std::uint64_t{x} >> (32 - t)];
    for (std::size_t j = 0; j < count.size(); ++j)
        if (count[j] != (n >> t))
            return "N = " + std::to_string(n) + ", stratum " + std::to_string(j) + " of " + std::to_string(count.size()) + " holds " +
                   std::to_string(count[j]);
    return "";
}

std::vector<std::unique_ptr<Sampler>> allSamplers(std::uint32_t spp, std::uint64_t seed) {
    std::vector<std::unique_ptr<Sampler>> v;
    for (const std::string& name : samplerNames()) v.push_back(makeSampler(name, spp, seed));
    return v;
}

bool sameBits(double a, double b) { return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b); }
bool sameBits(Point2 a, Point2 b) { return sameBits(a.u, b.u) && sameBits(a.v, b.v); }

constexpr std::uint64_t kFarDim = std::uint64_t{1} << 40;

}  // namespace

// ---------------------------------------------------------------------------------------------------
// building blocks

TEST(LowDiscrepancy, BitReversalAndSobolGenerators) {
    EXPECT_EQ(reverseBits32(1u), 0x80000000u);
    EXPECT_EQ(reverseBits32(0x80000000u), 1u);
    EXPECT_EQ(reverseBits32(0x0000FFFFu), 0xFFFF0000u);
    Rng rng(1, 2);
    for (int k = 0; k < 1000; ++k) {
        const std::uint32_t v = rng.bits();
        EXPECT_EQ(reverseBits32(reverseBits32(v)), v);
        std::uint32_t slow = 0;
        for (int b = 0; b < 32; ++b)
            if (v >> b & 1u) slow |= 0x80000000u >> b;
        EXPECT_EQ(reverseBits32(v), slow);
        EXPECT_EQ(sobolDimension0(v), slow);
    }
    // Dimension 1 from its definition, the upper-triangular Pascal matrix mod 2 (Sobol's second
    // dimension): output bit j (j = 0 the most significant) is the parity of the sum over index bits k
    // of C(k, j), j <= k, and C(k, j) is odd iff j's bits are a subset of k's (Lucas). (Column k is the
    // Sierpinski row k: 1, 11, 101, 1111, ... read from the top bit down.)
    auto sobol1Reference = [](std::uint32_t index) {
        std::uint32_t x = 0;
        for (int j = 0; j < 32; ++j) {
            unsigned parity = 0;
            for (int k = j; k < 32; ++k)
                if ((index >> k & 1u) && (k & j) == j) parity ^= 1u;
            if (parity) x |= 0x80000000u >> j;
        }
        return x;
    };
    EXPECT_EQ(sobolDimension1(1), 0x80000000u);
    EXPECT_EQ(sobolDimension1(2), 0xC0000000u);
    EXPECT_EQ(sobolDimension1(3), 0x40000000u);
    EXPECT_EQ(sobolDimension1(8), 0xF0000000u);
    for (std::uint32_t i = 0; i < 4096; ++i) {
        ASSERT_EQ(sobolDimension1Loop(i), sobol1Reference(i)) << "index " << i;
        ASSERT_EQ(sobolDimension1(i), sobol1Reference(i)) << "index " << i;
    }
    for (int k = 0; k < 1000; ++k) {
        const std::uint32_t i = rng.bits();
        ASSERT_EQ(sobolDimension1Loop(i), sobol1Reference(i)) << "index " << i;
        ASSERT_EQ(sobolDimension1(i), sobol1Reference(i)) << "index " << i;
    }
    for (int b = 0; b < 32; ++b) ASSERT_EQ(sobolDimension1(1u << b), sobol1Reference(1u << b)) << "index 2^" << b;
    EXPECT_LT(fixedToUnit(0xFFFFFFFFu), 1.0);
    EXPECT_EQ(fixedToUnit(0x80000000u), 0.5);
}

TEST(LowDiscrepancy, FusedScramblesEqualTheirDefinitions) {
    Rng rng(5, 6);
    for (int k = 0; k < 100000; ++k) {
        const std::uint32_t i = k < 4096 ? static_cast<std::uint32_t>(k) : rng.bits(), seed = rng.bits();
        ASSERT_EQ(owenScrambledSobol0(i, seed), owenScramble(sobolDimension0(i), seed)) << "index " << i << ", seed " << seed;
        ASSERT_EQ(owenScrambledSobol1(i, seed), owenScramble(sobolDimension1(i), seed)) << "index " << i << ", seed " << seed;
    }
}

TEST(LowDiscrepancy, OwenScramblesAreNestedBijections) {
    // Output digit k depends only on input digits 0..k (and the seed): inputs that share their first p
    // digits give outputs that share their first p digits. And digits 0..p-1 of the output are a
    // bijection of digits 0..p-1 of the input (checked for p = 16 on all 2^16 prefixes).
    using Scramble = std::function<std::uint32_t(std::uint32_t, std::uint32_t)>;
    const std::array<std::pair<const char*, Scramble>, 2> scrambles = {
        std::pair<const char*, Scramble>{"owenScramble", [](std::uint32_t v, std::uint32_t s) { return owenScramble(v, s); }},
        std::pair<const char*, Scramble>{"owenScrambleExact", [](std::uint32_t v, std::uint32_t s) { return owenScrambleExact(v, s); }}};
    Rng rng(7, 11);
    for (const auto& [name, scramble] : scrambles) {
        for (int trial = 0; trial < 2000; ++trial) {
            const std::uint32_t seed = rng.bits(), v = rng.bits();
            const int p = 1 + static_cast<int>(rng.bits() % 31);
            const std::uint32_t low = (1u << (32 - p)) - 1u;
            const std::uint32_t w = (v & ~low) | (rng.bits() & low);
            ASSERT_EQ(scramble(v, seed) >> (32 - p), scramble(w, seed) >> (32 - p))
                << name << ": seed " << seed << ", " << p << " shared digits, inputs " << v << " and " << w;
        }
        for (std::uint32_t seed : {0u, 1u, 0xFFFFFFFFu, 0x9E3779B9u}) {
            std::vector<bool> seen(1u << 16, false);
            for (std::uint32_t prefix = 0; prefix < (1u << 16); ++prefix) {
                const std::uint32_t out = scramble(prefix << 16 | (rng.bits() & 0xFFFFu), seed) >> 16;
                ASSERT_FALSE(seen[out]) << name << ": seed " << seed << ", prefix " << prefix << " collides";
                seen[out] = true;
            }
        }
    }
    // The checker has power: a hash of the whole value XORed in is not nested.
    int violations = 0;
    for (int trial = 0; trial < 100; ++trial) {
        const std::uint32_t v = rng.bits(), w = (v & 0xFFFF0000u) | (rng.bits() & 0xFFFFu);
        if (((v ^ hash32(v)) >> 16) != ((w ^ hash32(w)) >> 16)) ++violations;
    }
    EXPECT_GT(violations, 90);
}

TEST(LowDiscrepancy, ScrambledSobolPairsAreNets) {
    // (owen(sobol0(i), s0), owen(sobol1(i), s1)) over any aligned block of 2^k indices is a (0,k,2)-net,
    // for both Owen scramblers and without scrambling.
    const std::array<std::pair<std::uint32_t, std::uint32_t>, 5> seeds = {
        {{0u, 0u}, {1u, 2u}, {0xFFFFFFFFu, 0x12345678u}, {0x9E3779B9u, 0x7F4A7C15u}, {hash32(5), hash32(6)}}};
    for (int k = 0; k <= 12; ++k) {
        const std::uint32_t n = 1u << k;
        for (std::uint32_t block : {0u, 1u, 5u, (1u << 19) + 3u}) {
            if (block > (0xFFFFFFFFu >> k)) continue;
            const std::uint32_t first = block << k;
            std::vector<FixedPoint> plain(n);
            for (std::uint32_t i = 0; i < n; ++i) plain[i] = {sobolDimension0(first + i), sobolDimension1(first + i)};
            EXPECT_EQ(netFailure(plain), "") << "unscrambled, k = " << k << ", block " << block;
            for (const auto& [s0, s1] : seeds) {
                std::vector<FixedPoint> fast(n), exact(n);
                for (std::uint32_t i = 0; i < n; ++i) {
                    fast[i] = {owenScramble(plain[i][0], s0), owenScramble(plain[i][1], s1)};
                    exact[i] = {owenScrambleExact(plain[i][0], s0), owenScrambleExact(plain[i][1], s1)};
                }
                EXPECT_EQ(netFailure(fast), "") << "owenScramble, k = " << k << ", block " << block << ", seeds " << s0 << ", " << s1;
                EXPECT_EQ(netFailure(exact), "") << "owenScrambleExact, k = " << k << ", block " << block << ", seeds " << s0 << ", " << s1;
            }
        }
    }
}

// Block points (--splitting ears's first-hit continuations): for a pixel of 2^k samples, sample a's
// continuations 0..n-1 (n = 1, 2, 4, 8) are an aligned block of n points of the sequence (a (0, log2 n, 2)-net,
// checked as the points themselves), and continuation j of all 2^k samples is a (0,k,2)-net, unscrambled and
// Owen-scrambled, for every j; the union is every point of the first 8 x 2^k once. Against a map that
// ignores a (f = 0: every continuation 0 in one eighth of the first coordinate), which the check rejects.
TEST(LowDiscrepancy, BlockPointsAreNetsPerSampleAndPerContinuation) {
    for (std::uint32_t k = 0; k <= 14; ++k) {
        const std::uint32_t count = 1u << k;
        std::vector<int> seen(count * kBlockSize, 0);
        for (std::uint32_t a = 0; a < count; ++a)
            for (std::uint32_t n = 1; n <= kBlockSize; n *= 2) {
                std::vector<FixedPoint> own(n);
                std::vector<std::uint32_t> indices(n);
                for (std::uint32_t j = 0; j < n; ++j) {
                    const std::uint32_t point = blockPoint(a, k, j);
                    indices[j] = point;
                    own[j] = {sobolDimension0(point), sobolDimension1(point)};
                    if (n == kBlockSize) ++seen[point];
                }
                std::sort(indices.begin(), indices.end());
                ASSERT_EQ(indices.front() % n, 0u) << "k " << k << ", sample " << a << ", n " << n;
                ASSERT_EQ(indices.back(), indices.front() + n - 1) << "k " << k << ", sample " << a << ", n " << n;
                if (k <= 6) {
                    ASSERT_EQ(netFailure(own), "") << "k " << k << ", sample " << a << ", n " << n;
                }
            }
        EXPECT_EQ(std::count(seen.begin(), seen.end(), 1), static_cast<long>(count * kBlockSize)) << "k " << k;
        for (std::uint32_t j = 0; j < kBlockSize; ++j) {
            std::vector<FixedPoint> plain(count), scrambled(count), ignoring(count);
            for (std::uint32_t a = 0; a < count; ++a) {
                const std::uint32_t point = blockPoint(a, k, j);
                plain[a] = {sobolDimension0(point), sobolDimension1(point)};
                scrambled[a] = {owenScrambledSobol0(point, 0x9E3779B9u), owenScrambledSobol1(point, hash32(k))};
                ignoring[a] = {sobolDimension0(a * kBlockSize + j), sobolDimension1(a * kBlockSize + j)};
            }
            EXPECT_EQ(netFailure(plain), "") << "k " << k << ", continuation " << j;
            EXPECT_EQ(netFailure(scrambled), "") << "k " << k << ", continuation " << j;
            if (k >= 1) {
                EXPECT_NE(netFailure(ignoring), "") << "k " << k << ", continuation " << j;
            }
        }
    }
}

TEST(LowDiscrepancy, NetCheckerRejectsBrokenPairs) {
    // Power: pairs that are not (0,2)-sequences fail the same check for every k >= 2 (k = 0, 1 have
    // too few points to tell).
    for (int k = 2; k <= 10; ++k) {
        const std::uint32_t n = 1u << k;
        std::vector<FixedPoint> diagonal(n), shifted(n), scrambledDiagonal(n), notNested(n);
        for (std::uint32_t i = 0; i < n; ++i) {
            diagonal[i] = {sobolDimension0(i), sobolDimension0(i)};      // dimension 1 replaced by 0
            shifted[i] = {sobolDimension0(i), sobolDimension1(i) >> 1};  // y's bits shifted
            scrambledDiagonal[i] = {owenScramble(sobolDimension0(i), 3u), owenScramble(sobolDimension0(i), 4u)};
            notNested[i] = {sobolDimension0(i) ^ (hash32(i) & 0xC0000000u), sobolDimension1(i)};  // top digits randomised
        }
        EXPECT_NE(netFailure(diagonal), "") << "k = " << k;
        EXPECT_NE(netFailure(shifted), "") << "k = " << k;
        EXPECT_NE(netFailure(scrambledDiagonal), "") << "k = " << k;
        EXPECT_NE(netFailure(notNested), "") << "k = " << k;
    }
}

namespace {

using Permutation = std::function<std::uint32_t(std::uint32_t i, std::uint32_t n, std::uint32_t seed)>;

/// "" if i -> perm(i, n, seed), i < n, is a permutation of {0..n-1}, else what is wrong.
std::string permutationFailure(const Permutation& perm, std::uint32_t n, std::uint32_t seed) {
    std::vector<int> hits(n, 0);
    for (std::uint32_t i = 0; i < n; ++i) {
        const std::uint32_t j = perm(i, n, seed);
        if (j >= n) return "image of " + std::to_string(i) + " is " + std::to_string(j) + " >= n";
        ++hits[j];
    }
    const auto distinct = std::count_if(hits.begin(), hits.end(), [](int h) { return h > 0; });
    return distinct == static_cast<long>(n) ? "" : "only " + std::to_string(distinct) + " distinct values";
}

std::vector<std::uint32_t> permutationSeeds() {
    // Edge seeds (0, all ones, just below 2^32: where i + seed wraps) and hashed ones.
    std::vector<std::uint32_t> seeds = {0u, 1u, 2u, 3u, 0x7FFFFFFFu, 0x80000000u, 0xFFFFFF00u, 0xFFFFFFFEu, 0xFFFFFFFFu};
    for (std::uint32_t k = 0; k < 8; ++k) seeds.push_back(hash32(k + 100));
    return seeds;
}

}  // namespace

TEST(LowDiscrepancy, PermuteIndexIsAPermutation) {
    const Permutation kensler = [](std::uint32_t i, std::uint32_t n, std::uint32_t s) { return permuteIndex(i, n, s); };
    const Permutation any = [](std::uint32_t i, std::uint32_t n, std::uint32_t s) { return permuteAny(i, n, s); };
    for (std::uint32_t n : {1u, 2u, 3u, 5u, 16u, 24u, 100u, 1000u})
        for (std::uint32_t seed : permutationSeeds()) {
            EXPECT_EQ(permutationFailure(kensler, n, seed), "") << "permuteIndex, n = " << n << ", seed 0x" << std::hex << seed;
            EXPECT_EQ(permutationFailure(any, n, seed), "") << "permuteAny, n = " << n << ", seed 0x" << std::hex << seed;
        }
}

TEST(LowDiscrepancy, PermutePowerOfTwoIsAPermutation) {
    const Permutation pow2 = [](std::uint32_t i, std::uint32_t n, std::uint32_t s) {
        return permutePowerOfTwo(i, static_cast<std::uint32_t>(std::countr_zero(n)), s);
    };
    for (std::uint32_t k = 0; k <= 14; ++k)
        for (std::uint32_t seed : permutationSeeds())
            EXPECT_EQ(permutationFailure(pow2, 1u << k, seed), "") << "k = " << k << ", seed 0x" << std::hex << seed;
}

TEST(LowDiscrepancy, PermutationsAreRandomOverSeeds) {
    // A padded sampler needs the permutations of different dimensions to be independent uniformly random
    // permutations. Over random seeds, the image of an index must be uniform, and so must the offset
    // (mod n) between the images of two indices (which a final rotation by the seed cannot fake: it
    // tests the hash itself). 200 n seeds per case.
    struct Case {
        const char* name;
        std::uint32_t n;
        Permutation perm;
    };
    const Permutation kensler = [](std::uint32_t i, std::uint32_t n, std::uint32_t s) { return permuteIndex(i, n, s); };
    const Permutation pow2 = [](std::uint32_t i, std::uint32_t n, std::uint32_t s) {
        return permutePowerOfTwo(i, static_cast<std::uint32_t>(std::countr_zero(n)), s);
    };
    // Kensler's hash (permuteIndex) fails this: offsets far from uniform at n = 4, 16 (chi2 400, 296),
    // 5 and 24 (chi2 56, 77); the samplers use permuteAny (GF(2^k) affine maps, cycle-walked).
    const Permutation any = [](std::uint32_t i, std::uint32_t n, std::uint32_t s) { return permuteAny(i, n, s); };
    (void)kensler;
    const std::vector<Case> cases = {{"permuteAny", 5, any},         {"permuteAny", 24, any},         {"permuteAny", 100, any},
                                     {"permutePowerOfTwo", 4, pow2}, {"permutePowerOfTwo", 16, pow2}, {"permutePowerOfTwo", 64, pow2}};
    const int runs = 2 * static_cast<int>(cases.size());
    Rng rng(3, 4);
    for (const Case& c : cases) {
        std::vector<double> image(c.n, 0.0), offset(c.n - 1, 0.0);
        for (std::uint32_t trial = 0; trial < 200 * c.n; ++trial) {
            const std::uint32_t seed = rng.bits();
            const std::uint32_t a = c.perm(1, c.n, seed), b = c.perm(2, c.n, seed);
            image[a] += 1;
            offset[(b + c.n - a) % c.n - 1] += 1;
        }
        const Chi2 ci = chiSquareEqual(image), co = chiSquareEqual(offset);
        EXPECT_GE(ci.p, sidak(runs)) << c.name << ", n = " << c.n << ", image of index 1: " << ci.str();
        EXPECT_GE(co.p, sidak(runs)) << c.name << ", n = " << c.n << ", offset between the images of 1 and 2: " << co.str();
    }
}

// ---------------------------------------------------------------------------------------------------
// sobol sampler: nets and strata of each pixel

TEST(SobolSampler, PairsOfEveryPixelAreNets) {
    const std::array<std::uint64_t, 5> pixels = {0, 1, 777, 123456789, (std::uint64_t{1} << 40) + 3};
    const std::array<std::uint64_t, 7> dims = {0, 1, 2, 6, 100, 12345, kFarDim};
    for (std::uint64_t seed : {std::uint64_t{1}, std::uint64_t{0xDEADBEEFCAFEull}}) {
        for (int k = 0; k <= 10; ++k) {
            const std::uint32_t n = 1u << k;
            const SobolSampler sampler(n, seed);
            for (std::uint64_t pixel : pixels)
                for (std::uint64_t dim : dims) {
                    std::vector<FixedPoint> pts(n);
                    for (std::uint32_t i = 0; i < n; ++i) {
                        const Point2 p = sampler.sample2D(pixel, i, dim);
                        pts[i] = {toFixed(p.u), toFixed(p.v)};
                    }
                    EXPECT_EQ(netFailure(pts), "") << "seed " << seed << ", pixel " << pixel << ", dims (" << dim << ", " << dim + 1 << ")";
                }
        }
    }
}

// A sobol stream's block continuations: sample i's continuations 0..n-1 over a pixel of 16 samples are
// the points blockPoint(permuted i, 4, j) of the sampler's own scramble (a net among themselves and, for
// one j over the pixel, a net of 16), read through get2D at any dimension; other samplers get the split
// sub-sample.
TEST(SampleStream, BlockContinuationsAreNetsUnderSobol) {
    const std::uint32_t spp = 16;
    const SobolSampler sobol(spp, 7);
    for (std::uint64_t dim : {std::uint64_t{2}, std::uint64_t{1} << 40}) {
        const auto point = [&](std::uint32_t i, std::uint32_t j) {
            SampleStream s = SampleStream(sobol, 5, i).blockContinuation(j);
            s.setDimension(dim);
            const Point2 p = s.get2D();
            EXPECT_EQ(s.dimension(), dim + 2);
            return FixedPoint{toFixed(p.u), toFixed(p.v)};
        };
        for (std::uint32_t j = 0; j < kBlockSize; ++j) {
            std::vector<FixedPoint> across(spp);
            for (std::uint32_t i = 0; i < spp; ++i) across[i] = point(i, j);
            EXPECT_EQ(netFailure(across), "") << "continuation " << j << ", dim " << dim;
        }
        for (std::uint32_t i = 0; i < spp; ++i) {
            std::vector<FixedPoint> own(kBlockSize);
            for (std::uint32_t j = 0; j < kBlockSize; ++j) own[j] = point(i, j);
            EXPECT_EQ(netFailure(own), "") << "sample " << i << ", dim " << dim;
        }
    }
    const auto independent = makeSampler("independent", spp, 7);
    SampleStream block = SampleStream(*independent, 5, 3).blockContinuation(2), split = SampleStream(*independent, 5, 3).split(2, kBlockSize);
    block.setDimension(40), split.setDimension(40);
    const Point2 a = block.get2D(), b = split.get2D();
    EXPECT_EQ(a.u, b.u);
    EXPECT_EQ(a.v, b.v);
}

namespace {

/// (t, m, s)-net check for N = 2^m points in s dimensions (32-bit fixed point): every elementary box
/// prod_j [a_j/2^d_j, (a_j+1)/2^d_j) with sum d_j = m - t holds exactly 2^t points. "" or the failure.
std::string netFailureND(const std::vector<std::vector<std::uint32_t>>& pts, int t) {
    const std::size_t n = pts.size(), s = pts.front().size();
    const int m = std::countr_zero(n), total = m - t;
    std::vector<int> d(s, 0);
    std::string failure;
    // Every composition of `total` into s parts.
    std::function<void(std::size_t, int)> shapes = [&](std::size_t j, int left) {
        if (!failure.empty()) return;
        if (j + 1 == s) {
            d[j] = left;
            std::map<std::uint64_t, std::size_t> count;
            for (const auto& p : pts) {
                std::uint64_t key = 0;
                for (std::size_t k = 0; k < s; ++k) key = (key << d[k]) | (d[k] ? std::uint64_t{p[k]} >> (32 - d[k]) : 0);
                ++count[key];
            }
            const std::size_t boxes = std::size_t{1} << total;
            if (count.size() != boxes) failure = "a box is empty";
            for (const auto& [key, c] : count)
                if (c != (n >> total)) failure = "a box holds " + std::to_string(c) + " points instead of " + std::to_string(n >> total);
            return;
        }
        for (int k = 0; k <= left; ++k) {
            d[j] = k;
            shapes(j + 1, left - k);
        }
    };
    shapes(0, total);
    return failure;
}

}  // namespace

// Sobol' dimensions 2 and 3 (Joe and Kuo's 3 and 4): their direction numbers m_k from the integer form of
// the recurrence, m_k = 2 a_1 m_{k-1} ^ ... ^ 2^s m_{k-s} ^ m_{k-s}, against the matrix columns; the table
// look-up against the definition; each dimension's first 2^k points stratified.
TEST(LowDiscrepancy, SobolDimensionsTwoAndThree) {
    const std::uint32_t m2[] = {1, 3, 3, 9, 29}, m3[] = {1, 3, 1, 5, 31};
    for (int k = 1; k <= 5; ++k) {
        EXPECT_EQ(kSobolDimension2.column[k - 1], m2[k - 1] << (32 - k)) << "dimension 2, column " << k;
        EXPECT_EQ(kSobolDimension3.column[k - 1], m3[k - 1] << (32 - k)) << "dimension 3, column " << k;
    }
    Rng rng(1, 2);
    for (int i = 0; i < 10000; ++i) {
        const std::uint32_t index = static_cast<std::uint32_t>(rng.uniform() * 4294967296.0);
        ASSERT_EQ(kSobolDimension2(index), kSobolDimension2.byDefinition(index));
        ASSERT_EQ(kSobolDimension3(index), kSobolDimension3.byDefinition(index));
    }
    for (int k = 0; k <= 12; ++k) {
        std::vector<std::uint32_t> a(1u << k), b(1u << k);
        for (std::uint32_t i = 0; i < a.size(); ++i) a[i] = kSobolDimension2(i), b[i] = kSobolDimension3(i);
        EXPECT_EQ(strataFailure(a), "") << "dimension 2, k = " << k;
        EXPECT_EQ(strataFailure(b), "") << "dimension 3, k = " << k;
    }
}

// The joint first bounce: a pixel's position pair (dimension 0) and its joint pair (value2DJoint) are
// together the first four dimensions of an Owen-scrambled Sobol' sequence: a (3, m, 4)-net (t = the sum
// of the degrees of the primitive polynomials less one each: 0 + 0 + 1 + 2), whose 2D projections
// pairing a position dimension with a first-bounce dimension, and the first-bounce pair, are
// (1, m, 2)-nets at m = 6 (Joe and Kuo's direction numbers, chosen for good 2D projections;
// checked here by counting points in every elementary box). The padded pair at the same dimension is
// matched to the position pair at random: its cross projections fail for most pixels.
TEST(SobolSampler, JointPairAndPixelPairAreOneFourDimensionalNet) {
    constexpr std::uint32_t n = 64;
    const SobolSampler sampler(n, 9);
    int paddedFailures = 0;
    for (std::uint64_t pixel = 0; pixel < 20; ++pixel) {
        const std::uint64_t key = sampler.pixelKey(pixel);
        std::vector<std::vector<std::uint32_t>> joint(n), padded(n);
        for (std::uint32_t i = 0; i < n; ++i) {
            const Point2 px = sampler.value2D(key, i, n, 0), j = sampler.value2DJoint(key, i, n, kFarDim, 0),
                         p = sampler.value2D(key, i, n, kFarDim);
            joint[i] = {toFixed(px.u), toFixed(px.v), toFixed(j.u), toFixed(j.v)};
            padded[i] = {toFixed(px.u), toFixed(px.v), toFixed(p.u), toFixed(p.v)};
        }
        const auto project = [](const std::vector<std::vector<std::uint32_t>>& pts, int a, int b) {
            std::vector<std::vector<std::uint32_t>> out;
            for (const auto& p : pts) out.push_back({p[static_cast<std::size_t>(a)], p[static_cast<std::size_t>(b)]});
            return out;
        };
        EXPECT_EQ(netFailureND(joint, 3), "") << "pixel " << pixel;
        EXPECT_EQ(netFailureND(project(joint, 2, 3), 1), "") << "pixel " << pixel;
        bool paddedFails = false;
        for (int a : {0, 1})
            for (int b : {2, 3}) {
                EXPECT_EQ(netFailureND(project(joint, a, b), 1), "") << "pixel " << pixel << ", dimensions " << a << ", " << b;
                paddedFails = paddedFails || !netFailureND(project(padded, a, b), 1).empty();
            }
        paddedFailures += paddedFails ? 1 : 0;
    }
    EXPECT_GE(paddedFailures, 15);
}

// value3D (symmetric-mix's point and family offset): the same values as value2D and value2DJoint's first
// coordinate, bit for bit, for every sampler; under sobol the three are a (1, m, 3)-net (Sobol' dimensions
// 0, 1, 2: t = 0 + 0 + 1).
TEST(Samplers, Value3DIsThePairAndItsJointThirdCoordinate) {
    for (const auto& sampler : allSamplers(64, 4)) {
        for (std::uint64_t pixel : {0ull, 5ull}) {
            const std::uint64_t key = sampler->pixelKey(pixel);
            std::vector<std::vector<std::uint32_t>> pts;
            for (std::uint32_t i = 0; i < 64; ++i) {
                const Vec3 p = sampler->value3D(key, i, 64, kFarDim);
                const Point2 a = sampler->value2D(key, i, 64, kFarDim), b = sampler->value2DJoint(key, i, 64, kFarDim + 2, kFarDim);
                ASSERT_TRUE(sameBits(p.x, a.u) && sameBits(p.y, a.v) && sameBits(p.z, b.u)) << sampler->name();
                if (sampler->name() == "sobol") pts.push_back({toFixed(p.x), toFixed(p.y), toFixed(p.z)});
            }
            if (sampler->name() == "sobol") {
                EXPECT_EQ(netFailureND(pts, 1), "") << "pixel " << pixel;
            }
        }
    }
}

// --joint-first-bounce reads the first hit through a JointPairView: its one pair is value2DJoint, every
// other value (and the pixel keys) the sampler's own, bit for bit.
TEST(Samplers, JointPairViewRedirectsOnlyItsPair) {
    for (const auto& sampler : allSamplers(16, 8)) {
        const JointPairView view(*sampler, kFarDim, 0);
        EXPECT_EQ(view.pixelKey(7), sampler->pixelKey(7));
        const std::uint64_t key = sampler->pixelKey(7);
        for (std::uint32_t i = 0; i < 16; ++i) {
            EXPECT_TRUE(sameBits(view.value2D(key, i, 16, kFarDim), sampler->value2DJoint(key, i, 16, kFarDim, 0))) << sampler->name();
            EXPECT_TRUE(sameBits(view.value2D(key, i, 16, kFarDim + 2), sampler->value2D(key, i, 16, kFarDim + 2))) << sampler->name();
            EXPECT_TRUE(sameBits(view.value2D(key, i, 16, 0), sampler->value2D(key, i, 16, 0))) << sampler->name();
            EXPECT_TRUE(sameBits(view.value1D(key, i, 16, kFarDim), sampler->value1D(key, i, 16, kFarDim))) << sampler->name();
        }
    }
}

TEST(SobolSampler, OneDimensionsOfEveryPixelAreStratified) {
    for (std::uint64_t seed : {std::uint64_t{1}, std::uint64_t{0xDEADBEEFCAFEull}})
        for (int k = 0; k <= 10; ++k) {
            const std::uint32_t n = 1u << k;
            const SobolSampler sampler(n, seed);
            for (std::uint64_t pixel : {std::uint64_t{0}, std::uint64_t{42}, std::uint64_t{99999}})
                for (std::uint64_t dim : {std::uint64_t{0}, std::uint64_t{1}, std::uint64_t{7}, std::uint64_t{12345}, kFarDim}) {
                    std::vector<std::uint32_t> xs(n);
                    for (std::uint32_t i = 0; i < n; ++i) xs[i] = toFixed(sampler.sample1D(pixel, i, dim));
                    EXPECT_EQ(strataFailure(xs), "") << "seed " << seed << ", pixel " << pixel << ", dim " << dim;
                }
        }
}

TEST(SobolSampler, AnySppIsTheStartOfAScrambledSequence) {
    // spp = c 2^t points are the first spp points of a scrambled (0,2)-sequence: every elementary
    // interval of area 2^-t holds exactly c of them, and every 1D stratum of 2^-t exactly c.
    for (std::uint32_t spp : {3u, 6u, 12u, 24u, 40u, 96u, 100u, 320u}) {
        const SobolSampler sampler(spp, 2024);
        for (std::uint64_t pixel : {std::uint64_t{0}, std::uint64_t{5}, std::uint64_t{31337}})
            for (std::uint64_t dim : {std::uint64_t{0}, std::uint64_t{4}, std::uint64_t{999}, kFarDim}) {
                std::vector<FixedPoint> pts(spp);
                std::vector<std::uint32_t> xs(spp);
                for (std::uint32_t i = 0; i < spp; ++i) {
                    const Point2 p = sampler.sample2D(pixel, i, dim);
                    pts[i] = {toFixed(p.u), toFixed(p.v)};
                    xs[i] = toFixed(sampler.sample1D(pixel, i, dim));
                }
                EXPECT_EQ(netFailure(pts), "") << "spp " << spp << ", pixel " << pixel << ", dim " << dim;
                EXPECT_EQ(strataFailure(xs), "") << "spp " << spp << ", pixel " << pixel << ", dim " << dim;
            }
    }
}

// ---------------------------------------------------------------------------------------------------
// stratified sampler: strata of each pixel

TEST(StratifiedSampler, StrataOfEveryPixel) {
    // What sampler.h promises for N samples, m = floor(sqrt N), n = ceil(N/m): a 1D dimension has one
    // value in each [j/N, (j+1)/N); in a pair, y has one value in each [j/N, (j+1)/N), and x is in
    // column [c/m, (c+1)/m) and, inside it, in a sub-column of width 1/(mn) that no other sample uses
    // (the sample's row). The columns are filled like the first N cells of the m x n grid in row order,
    // so N mod m columns hold floor(N/m) + 1 samples and the others floor(N/m). For N = m n the pattern
    // is exactly multi-jittered: every cell [c/m, (c+1)/m) x [r/n, (r+1)/n) holds exactly one sample.
    for (std::uint32_t N : {1u, 2u, 3u, 5u, 7u, 12u, 16u, 17u, 64u}) {
        std::uint32_t m = 1;
        while ((m + 1) * (m + 1) <= N) ++m;
        const std::uint32_t n = (N + m - 1) / m;
        const StratifiedSampler sampler(N, 77);
        for (std::uint64_t pixel = 0; pixel < 40; ++pixel)
            for (std::uint64_t dim : {std::uint64_t{0}, std::uint64_t{3}, std::uint64_t{10}, kFarDim}) {
                const std::string where = "N = " + std::to_string(N) + ", pixel " + std::to_string(pixel) + ", dim " + std::to_string(dim);
                std::vector<int> strata1D(N), strataY(N), subColumns(m * n), columns(m), cells(m * n);
                for (std::uint32_t i = 0; i < N; ++i) {
                    const double x1 = sampler.sample1D(pixel, i, dim);
                    ASSERT_TRUE(x1 >= 0 && x1 < 1) << where;
                    ++strata1D[static_cast<std::size_t>(x1 * N)];
                    const Point2 p = sampler.sample2D(pixel, i, dim);
                    ASSERT_TRUE(p.u >= 0 && p.u < 1 && p.v >= 0 && p.v < 1) << where;
                    ++strataY[static_cast<std::size_t>(p.v * N)];
                    ++subColumns[static_cast<std::size_t>(p.u * (m * n))];
                    ++columns[static_cast<std::size_t>(p.u * m)];
                    ++cells[static_cast<std::size_t>(p.u * m) * n + static_cast<std::size_t>(p.v * n)];
                }
                EXPECT_TRUE(std::all_of(strata1D.begin(), strata1D.end(), [](int c) { return c == 1; })) << where << ": 1D strata";
                EXPECT_TRUE(std::all_of(strataY.begin(), strataY.end(), [](int c) { return c == 1; })) << where << ": y strata";
                EXPECT_TRUE(std::all_of(subColumns.begin(), subColumns.end(), [](int c) { return c <= 1; })) << where << ": x sub-columns";
                const int base = static_cast<int>(N / m);
                EXPECT_EQ(std::count(columns.begin(), columns.end(), base + 1), static_cast<long>(N % m)) << where << ": columns";
                EXPECT_EQ(std::count(columns.begin(), columns.end(), base), static_cast<long>(m - N % m)) << where << ": columns";
                if (N == m * n) {
                    EXPECT_TRUE(std::all_of(cells.begin(), cells.end(), [](int c) { return c == 1; })) << where << ": m x n cells";
                }
            }
    }
}

// ---------------------------------------------------------------------------------------------------
// every sampler: uniformity and independence

TEST(Samplers, EveryDimensionIsUniform) {
    // 4096 pixels x 16 samples, pooled. For the stratified and sobol samplers each pixel's 16 values fill
    // the 16 strata of 1/16, so the pooled chi-square is smaller than a chi-square variable: only its
    // upper tail (p < alpha) is a failure, which keeps the level below alpha. 64 bins test the coarse
    // shape, 1024 bins the values inside the strata (jitter, low scrambled digits).
    constexpr std::uint32_t kSpp = 16, kPixels = 4096;
    const std::array<int, 2> binCounts = {64, 1024};
    const int series = 6, runs = 3 * series * static_cast<int>(binCounts.size());
    for (const auto& sampler : allSamplers(kSpp, 12345)) {
        std::vector<std::vector<double>> values(series);
        const std::array<const char*, 6> names = {"1D dim 3", "pair 4 x", "pair 4 y", "1D dim 2^40+1", "pair 2^40+6 x", "pair 2^40+6 y"};
        for (std::uint64_t pixel = 0; pixel < kPixels; ++pixel)
            for (std::uint32_t i = 0; i < kSpp; ++i) {
                values[0].push_back(sampler->sample1D(pixel, i, 3));
                const Point2 p = sampler->sample2D(pixel, i, 4);
                values[1].push_back(p.u);
                values[2].push_back(p.v);
                values[3].push_back(sampler->sample1D(pixel, i, kFarDim + 1));
                const Point2 q = sampler->sample2D(pixel, i, kFarDim + 6);
                values[4].push_back(q.u);
                values[5].push_back(q.v);
            }
        for (int s = 0; s < series; ++s) {
            ASSERT_TRUE(std::all_of(values[s].begin(), values[s].end(), [](double x) { return x >= 0 && x < 1; }));
            for (int bins : binCounts) {
                const Chi2 c = chiSquareUniform(values[s], bins);
                EXPECT_GE(c.p, sidak(runs)) << sampler->name() << ", " << names[s] << ", " << bins << " bins: " << c.str();
            }
        }
    }
}

TEST(Samplers, UniformityCheckerRejectsNonUniformValues) {
    IndependentSampler sampler(16, 5);
    std::vector<double> squared, compressed;
    for (std::uint64_t pixel = 0; pixel < 4096; ++pixel)
        for (std::uint32_t i = 0; i < 16; ++i) {
            const double x = sampler.sample1D(pixel, i, 0);
            squared.push_back(x * x);
            compressed.push_back(0.98 * x);  // the top 2% never sampled
        }
    for (int bins : {64, 1024}) {
        EXPECT_LT(chiSquareUniform(squared, bins).p, 1e-6) << bins << " bins";
        EXPECT_LT(chiSquareUniform(compressed, bins).p, 1e-6) << bins << " bins";
    }
}

namespace {

/// A value source for the independence tests: (sampler, pixel, sample index) -> value.
using Source = std::function<double(const Sampler&, std::uint64_t, std::uint32_t)>;

struct SourcePair {
    const char* name;
    Source a, b;
};

std::vector<SourcePair> independencePairs() {
    return {
        {"1D dim 3 vs 1D dim 4", [](const Sampler& s, std::uint64_t px, std::uint32_t i) { return s.sample1D(px, i, 3); },
         [](const Sampler& s, std::uint64_t px, std::uint32_t i) { return s.sample1D(px, i, 4); }},
        {"pair 0 x vs pair 2 x", [](const Sampler& s, std::uint64_t px, std::uint32_t i) { return s.sample2D(px, i, 0).u; },
         [](const Sampler& s, std::uint64_t px, std::uint32_t i) { return s.sample2D(px, i, 2).u; }},
        {"pair 0 y vs 1D dim 12345", [](const Sampler& s, std::uint64_t px, std::uint32_t i) { return s.sample2D(px, i, 0).v; },
         [](const Sampler& s, std::uint64_t px, std::uint32_t i) { return s.sample1D(px, i, 12345); }},
        {"1D dim 9 vs pair 10 x", [](const Sampler& s, std::uint64_t px, std::uint32_t i) { return s.sample1D(px, i, 9); },
         [](const Sampler& s, std::uint64_t px, std::uint32_t i) { return s.sample2D(px, i, 10).u; }},
        {"pair 2^40 y vs pair 2^40+2 y", [](const Sampler& s, std::uint64_t px, std::uint32_t i) { return s.sample2D(px, i, kFarDim).v; },
         [](const Sampler& s, std::uint64_t px, std::uint32_t i) { return s.sample2D(px, i, kFarDim + 2).v; }},
    };
}

/// Across pixels: one sample per pixel (index = pixel mod spp), so the points are independent draws and
/// the chi-square against the uniform product on 16 x 16 cells has exactly 255 degrees of freedom, and
/// the correlation coefficient a standard error of 1/sqrt(N). (Pooling all of a pixel's samples would
/// not do: their joint strata make the statistic larger than a chi-square variable, by ~16/15.)
struct AcrossPixels {
    Chi2 chi2;
    double r = 0;
    std::size_t n = 0;
};
AcrossPixels acrossPixels(const Sampler& s, const Source& a, const Source& b, std::uint32_t pixels) {
    std::vector<double> xs, ys;
    for (std::uint64_t pixel = 0; pixel < pixels; ++pixel) {
        const std::uint32_t i = static_cast<std::uint32_t>(pixel % s.samplesPerPixel());
        xs.push_back(a(s, pixel, i));
        ys.push_back(b(s, pixel, i));
    }
    return {chiSquareUniform2D(xs, ys, 16), correlation(xs, ys), xs.size()};
}

/// Within pixels: the correlation r_p of the two dimensions over one pixel's n samples. If the pairing of
/// the two dimensions' values is a uniformly random permutation (what independent dimensions give,
/// stratified or not), E[r_p] = 0 and E[r_p^2] = 1/(n-1) exactly, whatever the values. Returns the
/// pixels' r_p and r_p^2 (independent across pixels: each has its own hashes).
std::pair<test::MeanStd, test::MeanStd> withinPixels(const Sampler& s, const Source& a, const Source& b, std::uint32_t pixels) {
    const std::uint32_t n = s.samplesPerPixel();
    std::vector<double> r, r2, xs(n), ys(n);
    for (std::uint64_t pixel = 0; pixel < pixels; ++pixel) {
        for (std::uint32_t i = 0; i < n; ++i) {
            xs[i] = a(s, pixel, i);
            ys[i] = b(s, pixel, i);
        }
        const double c = correlation(xs, ys);
        r.push_back(c);
        r2.push_back(c * c);
    }
    return {meanAndError(r), meanAndError(r2)};
}

}  // namespace

TEST(Samplers, DifferentDimensionsAreIndependentAcrossPixels) {
    constexpr std::uint32_t kSpp = 16;
    const auto pairs = independencePairs();
    const int runs = 3 * static_cast<int>(pairs.size() + 1);
    for (const auto& sampler : allSamplers(kSpp, 987654321)) {
        for (const SourcePair& pair : pairs) {
            const AcrossPixels across = acrossPixels(*sampler, pair.a, pair.b, 65536);
            EXPECT_GE(across.chi2.p, sidak(runs)) << sampler->name() << ", " << pair.name << ": " << across.chi2.str();
            EXPECT_LE(std::abs(across.r), 4.0 / std::sqrt(static_cast<double>(across.n))) << sampler->name() << ", " << pair.name;
        }
        // The two coordinates of one pair, for one sample of a random pixel, are independent uniforms too
        // (within a pixel they are jointly stratified, so only the across-pixel test applies).
        const AcrossPixels xy = acrossPixels(
            *sampler, [](const Sampler& s, std::uint64_t px, std::uint32_t i) { return s.sample2D(px, i, 6).u; },
            [](const Sampler& s, std::uint64_t px, std::uint32_t i) { return s.sample2D(px, i, 6).v; }, 65536);
        EXPECT_GE(xy.chi2.p, sidak(runs)) << sampler->name() << ", pair 6 x vs y: " << xy.chi2.str();
        EXPECT_LE(std::abs(xy.r), 4.0 / std::sqrt(static_cast<double>(xy.n))) << sampler->name() << ", pair 6 x vs y";
    }
}

TEST(Samplers, DifferentDimensionsAreIndependentWithinAPixel) {
    // The pixel's n samples of two different dimensions must be paired as by independent uniformly random
    // permutations (what padding promises, and what independent values give): E[r_p] = 0 and
    // E[r_p^2] = 1/(n-1). Larger E[r_p^2] means the two dimensions are correlated inside every pixel
    // (with a random sign), which adds variance to any integrand that couples them.
    const auto pairs = independencePairs();
    for (const auto& [spp, pixels] : {std::pair<std::uint32_t, std::uint32_t>{4, 4096}, {16, 4096}, {64, 1024}})
        for (const auto& sampler : allSamplers(spp, 987654321))
            for (const SourcePair& pair : pairs) {
                const auto [r, r2] = withinPixels(*sampler, pair.a, pair.b, pixels);
                EXPECT_LE(std::abs(r.mean), 4 * r.stdError)
                    << sampler->name() << ", spp " << spp << ", " << pair.name << ": mean within-pixel r";
                EXPECT_LE(std::abs(r2.mean - 1.0 / (spp - 1)), 4 * r2.stdError)
                    << sampler->name() << ", spp " << spp << ", " << pair.name << ": mean within-pixel r^2 = " << r2.mean << " +- "
                    << r2.stdError << ", expected " << 1.0 / (spp - 1);
            }
}

TEST(Samplers, IndependenceCheckersRejectDependentDimensions) {
    constexpr std::uint32_t kSpp = 16;
    const Source x = [](const Sampler& s, std::uint64_t px, std::uint32_t i) { return s.sample1D(px, i, 3); };
    const Source same = x;
    const Source mirrored = [](const Sampler& s, std::uint64_t px, std::uint32_t i) { return kOneBelow - s.sample1D(px, i, 3); };
    for (const auto& sampler : allSamplers(kSpp, 31)) {
        for (const Source& b : {same, mirrored}) {
            const AcrossPixels across = acrossPixels(*sampler, x, b, 65536);
            EXPECT_LT(across.chi2.p, 1e-6) << sampler->name();
            EXPECT_GT(std::abs(across.r), 0.99) << sampler->name();
            EXPECT_GT(withinPixels(*sampler, x, b, 256).second.mean, 0.99) << sampler->name();
        }
    }
    // A subtler dependence: two "padded" Sobol' dimensions that share the pixel's permutation of the
    // sample indices and differ only in their scrambles (the classic padding mistake). Across pixels the
    // values look independent, but within a pixel they are a nested-scramble image of each other.
    std::vector<double> r2;
    for (std::uint32_t pixel = 0; pixel < 4096; ++pixel) {
        const std::uint32_t permSeed = hash32(pixel), sa = hash32(pixel + 0x10000), sb = hash32(pixel + 0x20000);
        std::vector<double> xs(kSpp), ys(kSpp);
        for (std::uint32_t i = 0; i < kSpp; ++i) {
            const std::uint32_t j = permuteIndex(i, kSpp, permSeed);
            xs[i] = fixedToUnit(owenScramble(sobolDimension0(j), sa));
            ys[i] = fixedToUnit(owenScramble(sobolDimension0(j), sb));
        }
        const double c = correlation(xs, ys);
        r2.push_back(c * c);
    }
    const test::MeanStd m = meanAndError(r2);
    EXPECT_GT(std::abs(m.mean - 1.0 / (kSpp - 1)), 10 * m.stdError) << "shared permutation: mean r^2 = " << m.mean << " +- " << m.stdError;
}

// ---------------------------------------------------------------------------------------------------
// determinism, seeds, range

TEST(Samplers, NamesAndFactory) {
    EXPECT_EQ(samplerNames(), (std::vector<std::string>{"independent", "stratified", "sobol"}));
    for (const std::string& name : samplerNames()) {
        const auto s = makeSampler(name, 8, 3);
        EXPECT_EQ(s->name(), name);
        EXPECT_EQ(s->samplesPerPixel(), 8u);
        EXPECT_EQ(s->seed(), 3u);
        EXPECT_NE(samplerHelp().find(name), std::string::npos);
        EXPECT_EQ(makeSampler(name, 0, 3)->samplesPerPixel(), 1u);
    }
    EXPECT_NE(std::find(samplerNames().begin(), samplerNames().end(), std::string(kDefaultSampler)), samplerNames().end());
    EXPECT_THROW(makeSampler("halton", 8, 3), std::invalid_argument);
}

TEST(Samplers, ValuesArePureFunctionsOfSeedPixelIndexDimension) {
    for (const std::string& name : samplerNames()) {
        const auto a = makeSampler(name, 16, 42), b = makeSampler(name, 16, 42);
        for (std::uint64_t pixel : {std::uint64_t{0}, std::uint64_t{1}, std::uint64_t{99}, std::uint64_t{1} << 30, kFarDim + 5})
            for (std::uint32_t i : {0u, 7u, 15u})
                for (std::uint64_t dim :
                     {std::uint64_t{0}, std::uint64_t{1}, std::uint64_t{2}, std::uint64_t{5}, std::uint64_t{100}, kFarDim + 1}) {
                    const double v = a->sample1D(pixel, i, dim);
                    EXPECT_TRUE(sameBits(v, a->sample1D(pixel, i, dim))) << name;
                    EXPECT_TRUE(sameBits(v, b->sample1D(pixel, i, dim))) << name;
                    EXPECT_TRUE(sameBits(v, a->value1D(a->pixelKey(pixel), i, 16, dim))) << name;
                    const Point2 p = a->sample2D(pixel, i, dim);
                    EXPECT_TRUE(sameBits(p, a->sample2D(pixel, i, dim))) << name;
                    EXPECT_TRUE(sameBits(p, b->sample2D(pixel, i, dim))) << name;
                    EXPECT_TRUE(sameBits(p, a->value2D(a->pixelKey(pixel), i, 16, dim))) << name;
                }
        // Asking in another order changes nothing (no hidden state).
        const double late = a->sample1D(3, 4, 5);
        for (std::uint64_t dim = 0; dim < 100; ++dim) (void)a->sample2D(3, 4, dim);
        EXPECT_TRUE(sameBits(late, a->sample1D(3, 4, 5))) << name;
    }
}

// The independent sampler's pair at `dim` is the first two doubles of dimension `dim`'s generator, so
// its first value is the 1D value of `dim` (and its second is a value of its own).
TEST(IndependentSampler, PairStartsWithItsOneDimension) {
    const IndependentSampler sampler(16, 42);
    int mismatches = 0;
    for (std::uint64_t pixel = 0; pixel < 20; ++pixel)
        for (std::uint32_t i = 0; i < 16; ++i)
            for (std::uint64_t dim : {std::uint64_t{0}, std::uint64_t{1}, std::uint64_t{8}, kFarDim}) {
                const Point2 p = sampler.sample2D(pixel, i, dim);
                const double u = sampler.sample1D(pixel, i, dim), v = sampler.sample1D(pixel, i, dim + 1);
                if (!sameBits(p.u, u) || sameBits(p.v, v)) {
                    if (++mismatches <= 3)
                        ADD_FAILURE() << "pixel " << pixel << ", sample " << i << ", dim " << dim << ": sample2D = (" << p.u << ", " << p.v
                                      << "), (sample1D(dim), sample1D(dim+1)) = (" << u << ", " << v << "): u must equal, v must differ";
                }
            }
    EXPECT_EQ(mismatches, 0);
}

TEST(Samplers, SeedsPixelsAndDimensionsChangeTheValues) {
    // Values are 32-bit (stratified, sobol) or 53-bit (independent) hashes: for ~20000 comparisons the
    // expected number of coincidences is below 1e-5; allow 2.
    for (const std::string& name : samplerNames()) {
        for (std::uint32_t spp : {1u, 16u}) {
            const auto a = makeSampler(name, spp, 42), b = makeSampler(name, spp, 43);
            int sameSeed = 0, samePixel = 0, sameDim = 0, compared = 0;
            for (std::uint64_t pixel = 0; pixel < 64; ++pixel)
                for (std::uint32_t i = 0; i < spp; ++i)
                    for (std::uint64_t dim : {std::uint64_t{0}, std::uint64_t{1}, std::uint64_t{4}, std::uint64_t{33}, kFarDim}) {
                        const double v = a->sample1D(pixel, i, dim);
                        const Point2 p = a->sample2D(pixel, i, dim);
                        sameSeed += (v == b->sample1D(pixel, i, dim)) + (p.u == b->sample2D(pixel, i, dim).u) +
                                    (p.v == b->sample2D(pixel, i, dim).v);
                        samePixel += (v == a->sample1D(pixel + 1000, i, dim)) + (p.u == a->sample2D(pixel + 1000, i, dim).u);
                        sameDim += (v == a->sample1D(pixel, i, dim + 2)) + (p.u == a->sample2D(pixel, i, dim + 2).u);
                        ++compared;
                    }
            EXPECT_LE(sameSeed, 2) << name << ", spp " << spp << ": " << sameSeed << " of " << 3 * compared
                                   << " values equal under seeds 42 and 43";
            EXPECT_LE(samePixel, 2) << name << ", spp " << spp << ": pixels p and p + 1000";
            EXPECT_LE(sameDim, 2) << name << ", spp " << spp << ": dimensions d and d + 2";
        }
    }
}

TEST(Samplers, ValuesLieInTheUnitInterval) {
    auto inUnit = [](double x) { return x >= 0 && x < 1; };
    for (std::uint32_t spp : {1u, 2u, 3u, 16u, 1000u, 1u << 20, 0xFFFFFFFFu}) {
        for (const auto& sampler : allSamplers(spp, 8)) {
            std::vector<std::uint32_t> indices = {0u, spp - 1, spp / 2};
            if (spp >= 4) indices.push_back(spp - 2);
            std::vector<std::uint64_t> dims;
            for (std::uint64_t d = 0; d < 40; ++d) dims.push_back(d);
            for (std::uint64_t d = kFarDim - 4; d < kFarDim + 4; ++d) dims.push_back(d);
            dims.push_back(~std::uint64_t{0} - 1);
            for (std::uint64_t pixel = 0; pixel < 64; ++pixel)
                for (std::uint32_t i : indices)
                    for (std::uint64_t dim : dims) {
                        const double v = sampler->sample1D(pixel, i, dim);
                        const Point2 p = sampler->sample2D(pixel, i, dim);
                        ASSERT_TRUE(inUnit(v) && inUnit(p.u) && inUnit(p.v))
                            << sampler->name() << ", spp " << spp << ", pixel " << pixel << ", sample " << i << ", dim " << dim << ": " << v
                            << ", (" << p.u << ", " << p.v << ")";
                    }
        }
    }
}

// ---------------------------------------------------------------------------------------------------
// SampleStream

TEST(SampleStream, HandsOutConsecutiveDimensions) {
    for (const auto& sampler : allSamplers(16, 99)) {
        const std::uint64_t pixel = 77;
        const std::uint32_t index = 5;
        const std::uint64_t key = sampler->pixelKey(pixel);
        SampleStream fresh(*sampler, pixel, index);
        EXPECT_EQ(fresh.dimension(), 0u);
        EXPECT_TRUE(sameBits(fresh.get2D(), sampler->sample2D(pixel, index, 0)));
        EXPECT_EQ(fresh.pixel(), pixel);
        EXPECT_EQ(fresh.sampleIndex(), index);
        EXPECT_EQ(fresh.samplesPerPixel(), 16u);
        EXPECT_EQ(fresh.seed(), 99u);

        SampleStream st(*sampler, pixel, index, 3);
        EXPECT_EQ(st.dimension(), 3u);
        EXPECT_TRUE(sameBits(st.get1D(), sampler->sample1D(pixel, index, 3)));
        EXPECT_EQ(st.dimension(), 4u);
        EXPECT_TRUE(sameBits(st.get1D(), sampler->sample1D(pixel, index, 4)));
        EXPECT_EQ(st.dimension(), 5u);
        EXPECT_TRUE(sameBits(st.get2D(), sampler->sample2D(pixel, index, 5)));
        EXPECT_EQ(st.dimension(), 7u);
        EXPECT_TRUE(sameBits(st.get2D(), sampler->sample2D(pixel, index, 7)));
        EXPECT_EQ(st.dimension(), 9u);
        st.setDimension(kFarDim);
        EXPECT_EQ(st.dimension(), kFarDim);
        EXPECT_TRUE(sameBits(st.get1D(), sampler->sample1D(pixel, index, kFarDim)));
        st.setDimension(100);
        // get2DOf: another sample's values of the current pair, in a pattern of `count` samples.
        EXPECT_TRUE(sameBits(st.get2DOf(11, 16), sampler->sample2D(pixel, 11, 100)));
        EXPECT_EQ(st.dimension(), 102u);
        EXPECT_TRUE(sameBits(st.get2DOf(2, 4), sampler->value2D(key, 2, 4, 102)));
        EXPECT_EQ(st.dimension(), 104u);
        EXPECT_TRUE(sameBits(st.get2D(), sampler->sample2D(pixel, index, 104)));

        // roundPoint: sample `round` of a pattern of ceil(spp / entries) samples.
        SampleStream rs(*sampler, pixel, 13, 20);
        EXPECT_EQ(rs.patternRounds(6), 3u);
        EXPECT_EQ(rs.patternRound(6), 2u);
        EXPECT_TRUE(sameBits(rs.roundPoint(6), sampler->value2D(key, 2, 3, 20)));
        EXPECT_EQ(rs.dimension(), 22u);
    }
}

TEST(SampleStream, SmallPatternsAreStratifiedToo) {
    // get2DOf(i, count), i < count: the pattern of `count` points is itself stratified.
    for (std::uint32_t count : {2u, 4u, 8u}) {
        const SobolSampler sobol(64, 5);
        const StratifiedSampler stratified(64, 5);
        for (std::uint64_t pixel = 0; pixel < 16; ++pixel) {
            std::vector<FixedPoint> pts(count);
            std::vector<int> strataY(count);
            for (std::uint32_t i = 0; i < count; ++i) {
                SampleStream a(sobol, pixel, 0, 30), b(stratified, pixel, 0, 30);
                const Point2 p = a.get2DOf(i, count);
                pts[i] = {toFixed(p.u), toFixed(p.v)};
                ++strataY[static_cast<std::size_t>(b.get2DOf(i, count).v * count)];
            }
            EXPECT_EQ(netFailure(pts), "") << "sobol, count " << count << ", pixel " << pixel;
            EXPECT_TRUE(std::all_of(strataY.begin(), strataY.end(), [](int c) { return c == 1; })) << "stratified, count " << count;
        }
    }
}

TEST(SampleStream, PatternEntriesFillEachRound) {
    // Each round of `entries` consecutive samples takes every entry once (a partial last round takes
    // distinct entries); over pixels, a given sample's entry is uniform. Each call uses one dimension.
    const int runs = 3 * 2;
    for (const auto& sampler : allSamplers(10, 4)) {
        for (std::uint32_t entries : {4u, 5u}) {
            for (std::uint64_t pixel = 0; pixel < 50; ++pixel) {
                std::vector<std::set<std::uint32_t>> rounds((10 + entries - 1) / entries);
                for (std::uint32_t i = 0; i < 10; ++i) {
                    SampleStream st(*sampler, pixel, i, 12);
                    const std::uint32_t e = st.patternEntry(entries);
                    EXPECT_EQ(st.dimension(), 13u);
                    ASSERT_LT(e, entries);
                    EXPECT_TRUE(rounds[i / entries].insert(e).second)
                        << sampler->name() << ", entries " << entries << ", pixel " << pixel << ", sample " << i;
                }
            }
            std::vector<double> counts(entries, 0.0);
            for (std::uint64_t pixel = 0; pixel < 20000; ++pixel) {
                SampleStream st(*sampler, pixel, 7, 12);
                counts[st.patternEntry(entries)] += 1;
            }
            const Chi2 c = chiSquareEqual(counts);
            EXPECT_GE(c.p, sidak(runs)) << sampler->name() << ", entries " << entries << ": " << c.str();
        }
    }
}

// The alias table picks index i with probability w_i / sum w and hands on a u that is uniform within the
// pick. With u on a grid of N points each frequency is within (entries + 1) / N of its probability (each
// cell of the table is an interval of u cut in at most two); the remapped u's mean per index within 4
// standard errors of 1/2 (sd 1/sqrt(12 count)).
TEST(AliasTable, PicksInProportionToItsWeightsAndRemapsUniformly) {
    const std::vector<double> w = {3, 0, 1, 6, 0.5, 1e-3, 2};
    const AliasTable table(w);
    double total = 0;
    for (double x : w) total += x;
    EXPECT_DOUBLE_EQ(table.total(), total);
    const int n = 200000;
    std::vector<int> count(w.size(), 0);
    std::vector<double> sumU(w.size(), 0.0);
    for (int i = 0; i < n; ++i) {
        double u = -1;
        const std::size_t k = table.sample((i + 0.5) / n, u);
        ASSERT_LT(k, w.size());
        ASSERT_GE(u, 0.0);
        ASSERT_LT(u, 1.0);
        ++count[k];
        sumU[k] += u;
    }
    for (std::size_t k = 0; k < w.size(); ++k) {
        EXPECT_DOUBLE_EQ(table.pmf(k), w[k] / total);
        EXPECT_NEAR(count[k] / double(n), w[k] / total, double(w.size() + 1) / n) << "index " << k;
        if (count[k] > 100) {
            EXPECT_NEAR(sumU[k] / count[k], 0.5, 4.0 / std::sqrt(12.0 * count[k])) << "index " << k;
        }
    }
    EXPECT_EQ(count[1], 0) << "a zero weight is never chosen";
    double u = 0;
    EXPECT_EQ(AliasTable({0.0, 2.0, 0.0}).sample(0.01, u), 1u) << "whatever u, the only weight";
}

// The Sobol' sampler's inline path (SampleStream without the virtual call, permuteSamples' table fast
// path) against the definition written out: the same bits for every count, dimension and key tried.
TEST(LowDiscrepancy, InlineSobolValuesEqualTheirDefinition) {
    const std::uint32_t counts[] = {1, 2, 3, 16, 64, 100, 128, 1024, 2048, 5000};
    const std::uint64_t dims[] = {0, 7, 130, (1ull << 40) + 3};
    for (std::uint64_t key : {std::uint64_t{1}, mixSeed(42, 77), ~std::uint64_t{0}})
        for (std::uint32_t n : counts)
            for (std::uint64_t dim : dims)
                for (std::uint32_t i = 0; i < n; i += 1 + n / 37) {
                    const std::uint64_t h = mixSeed(key, 2 * dim);
                    const auto seed = static_cast<std::uint32_t>((h * 0xD6E8FEB86659FD93ull) >> 32);
                    ASSERT_EQ(permuteSamples(i, n, seed), permuteAny(i, n, seed)) << n << " " << i;
                    const std::uint32_t j = permuteAny(i, n, seed);
                    const Point2 p = SobolSampler::pairValue(key, i, n, dim);
                    ASSERT_EQ(p.u, fixedToUnit(owenScramble(sobolDimension0(j), static_cast<std::uint32_t>(h))));
                    ASSERT_EQ(p.v, fixedToUnit(owenScramble(sobolDimension1(j), static_cast<std::uint32_t>(h >> 32))));
                    const std::uint64_t h1 = mixSeed(key, 2 * dim + 1);
                    const std::uint32_t j1 = permuteAny(i, n, static_cast<std::uint32_t>(h1 >> 32));
                    ASSERT_EQ(SobolSampler::singleValue(key, i, n, dim),
                              fixedToUnit(owenScramble(sobolDimension0(j1), static_cast<std::uint32_t>(h1))));
                }
    // A stream reads the inline values from a Sobol' sampler and the view's from a JointPairView of it.
    const auto sobol = makeSampler("sobol", 64, 5);
    SampleStream s(*sobol, 1234, 17, 6);
    const Point2 a = s.get2D();
    const double b = s.get1D();
    const Point2 a2 = sobol->value2D(sobol->pixelKey(1234), 17, 64, 6);
    EXPECT_EQ(a.u, a2.u);
    EXPECT_EQ(a.v, a2.v);
    EXPECT_EQ(b, sobol->value1D(sobol->pixelKey(1234), 17, 64, 8));
    const JointPairView joint(*sobol, 6, 0);
    SampleStream viaJoint = SampleStream(*sobol, 1234, 17, 6).through(joint);
    const Point2 c = viaJoint.get2D(), c2 = sobol->value2DJoint(sobol->pixelKey(1234), 17, 64, 6, 0);
    EXPECT_EQ(c.u, c2.u);
    EXPECT_EQ(c.v, c2.v);
}

// sampling/sobol_lanes.h: many streams' values at once, in vector lanes where the processor has them, against
// SobolSampler's scalar definition one stream at a time: equal bit for bit, for every pattern size the lanes take
// (1 and the powers of two up to 2^10), sizes they hand back to the scalar form, and counts of streams that leave a
// part of a lane group empty.
TEST(SobolLanes, ValuesEqualTheScalarDefinitionBitForBit) {
    Rng rng(41, 3);
    std::vector<std::uint32_t> counts = {1, 2, 4, 8, 16, 32, 64, 128, 256, 512, 1024, 3, 21, 37, 2048, 4096};
    const bool lanes = sobolLanesAvailable();
    if (!lanes) std::printf("[ NOTE     ] no AVX-512/GFNI here: the dispatching calls run the scalar form\n");
    std::size_t checked = 0;
    for (std::uint32_t count : counts)
        for (std::size_t n : {std::size_t{1}, std::size_t{7}, std::size_t{8}, std::size_t{16}, std::size_t{61}, std::size_t{256}}) {
            std::vector<std::uint64_t> keys(n);
            std::vector<std::uint32_t> indices(n);
            for (std::size_t i = 0; i < n; ++i) {
                keys[i] = (static_cast<std::uint64_t>(rng.bits()) << 32) | rng.bits();
                indices[i] = rng.bits() % count;
            }
            const std::uint64_t dim = rng.bits() % 100000;
            std::vector<double> us(n), vs(n), singles(n), laneUs(n), laneVs(n), laneSingles(n);
            sobolPairValues(keys.data(), indices.data(), count, dim, n, us.data(), vs.data());
            sobolSingleValues(keys.data(), indices.data(), count, dim, n, singles.data());
            for (std::size_t i = 0; i < n; ++i) {
                const Point2 p = SobolSampler::pairValue(keys[i], indices[i], count, dim);
                ASSERT_EQ(us[i], p.u) << "count " << count << " stream " << i << " of " << n;
                ASSERT_EQ(vs[i], p.v) << "count " << count << " stream " << i << " of " << n;
                ASSERT_EQ(singles[i], SobolSampler::singleValue(keys[i], indices[i], count, dim)) << "count " << count << " stream " << i;
                ++checked;
            }
            if (!lanes) continue;
            detail::sobolPairValuesLanes(keys.data(), indices.data(), count, dim, n, laneUs.data(), laneVs.data());
            detail::sobolSingleValuesLanes(keys.data(), indices.data(), count, dim, n, laneSingles.data());
            EXPECT_EQ(laneUs, us) << "count " << count << ", " << n << " streams";
            EXPECT_EQ(laneVs, vs) << "count " << count << ", " << n << " streams";
            EXPECT_EQ(laneSingles, singles) << "count " << count << ", " << n << " streams";
        }
    EXPECT_EQ(checked, counts.size() * (1 + 7 + 8 + 16 + 61 + 256));
}

// SampleStream::readAhead: a stream reads a value given ahead at exactly its dimension (the wavefront tracer's
// values from the lanes), and its own value everywhere else; a sub-sample, a block continuation and a stream of
// another sampler never read them.
TEST(SampleStream, ReadsValuesAheadAtTheirDimensionsOnly) {
    const SobolSampler sobol(16, 9);
    AheadValues ahead;
    ahead.pairDims[0] = 10;
    ahead.pairs[0] = {0.125, 0.375};  // not the sampler's values there: a read of them is seen
    ahead.pairDims[1] = 20;
    ahead.pairs[1] = {0.625, 0.875};
    ahead.singleDim = 31;
    ahead.single = 0.5625;
    SampleStream plain(sobol, 77, 5), read(sobol, 77, 5);
    read.readAhead(&ahead);
    for (std::uint64_t dim : {8u, 10u, 12u, 20u, 22u}) {
        plain.setDimension(dim);
        read.setDimension(dim);
        const Point2 want = dim == 10 ? ahead.pairs[0] : dim == 20 ? ahead.pairs[1] : plain.get2D();
        const Point2 got = read.get2D();
        EXPECT_EQ(got.u, want.u) << "dimension " << dim;
        EXPECT_EQ(got.v, want.v) << "dimension " << dim;
        EXPECT_EQ(read.dimension(), dim + 2) << "a pair read ahead still moves the stream on";
    }
    for (std::uint64_t dim : {30u, 31u, 32u}) {
        plain.setDimension(dim);
        read.setDimension(dim);
        EXPECT_EQ(read.get1D(), dim == 31 ? ahead.single : plain.get1D()) << "dimension " << dim;
    }
    const Point2 own = SobolSampler::pairValue(sobol.pixelKey(77), 5, 16, 10);
    EXPECT_NE(own.u, ahead.pairs[0].u) << "the test's values ahead must differ from the sampler's";
    SampleStream sub = read.split(1, 2);
    sub.setDimension(10);
    const Point2 subOwn = SobolSampler::pairValue(sobol.pixelKey(77), 11, 32, 10);
    EXPECT_EQ(sub.get2D().u, subOwn.u) << "a sub-sample has values of its own";
    SampleStream block = SampleStream(sobol, 77, 5).blockContinuation(1);
    SampleStream blockRead = block;
    blockRead.readAhead(&ahead);
    block.setDimension(10);
    blockRead.setDimension(10);
    EXPECT_EQ(blockRead.get2D().u, block.get2D().u) << "a block continuation reads block points";
    const IndependentSampler independent(16, 9);
    SampleStream other(independent, 77, 5), otherRead(independent, 77, 5);
    otherRead.readAhead(&ahead);
    other.setDimension(10);
    otherRead.setDimension(10);
    EXPECT_EQ(otherRead.get2D().u, other.get2D().u) << "values ahead are the sobol sampler's";
    read.readAhead(nullptr);
    read.setDimension(10);
    EXPECT_EQ(read.get2D().u, own.u) << "no longer after readAhead(nullptr)";
}
