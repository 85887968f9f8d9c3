// The sobol sampler's values in lanes (sobol_lanes.h): the scalar definitions of sampler.h and
// lowdiscrepancy.h step by step, eight streams a vector.
#include "sampling/sobol_lanes.h"

#include "sampling/lowdiscrepancy.h"
#include "sampling/rng.h"
#include "sampling/sampler.h"
#include "sampling/x86_lanes.h"

#include <bit>

namespace symphong {

namespace detail {

void sobolPairValuesScalar(const std::uint64_t* keys, const std::uint32_t* indices, std::uint32_t count, std::uint64_t dim, std::size_t n,
                           double* us, double* vs) {
    for (std::size_t i = 0; i < n; ++i) {
        const Point2 p = SobolSampler::pairValue(keys[i], indices[i], count, dim);
        us[i] = p.u;
        vs[i] = p.v;
    }
}

void sobolSingleValuesScalar(const std::uint64_t* keys, const std::uint32_t* indices, std::uint32_t count, std::uint64_t dim, std::size_t n,
                             double* out) {
    for (std::size_t i = 0; i < n; ++i) out[i] = SobolSampler::singleValue(keys[i], indices[i], count, dim);
}

}  // namespace detail

#ifdef SYMPHONG_X86_LANES

namespace {

#define SYMPHONG_LANES_TARGET __attribute__((target("avx512f,avx512dq,avx512bw,avx512vl,gfni"), always_inline)) inline

/// The pattern sizes the lanes take: 1, or a power of two whose permutation is permutePowerOfTwo's table
/// look-ups (permuteSamples' common case). The permuted index is then below 2^10, so Sobol' dimension 1
/// needs only its two low bytes' tables.
bool lanesTake(std::uint32_t count) {
    static_assert(detail::GfTables::kMaxK <= 16, "a permuted index of two bytes");
    return count == 1 || (count <= (1u << detail::GfTables::kMaxK) && (count & (count - 1)) == 0);
}

SYMPHONG_LANES_TARGET __m512i set64(std::uint64_t v) { return _mm512_set1_epi64(static_cast<long long>(v)); }
SYMPHONG_LANES_TARGET __m256i set32(std::uint32_t v) { return _mm256_set1_epi32(static_cast<int>(v)); }

/// mixSeed(key, index) of eight keys (rng.h, SplitMix64's finaliser): seed x c + index + c' as one sum mod 2^64.
SYMPHONG_LANES_TARGET __m512i mixSeedLanes(__m512i key, std::uint64_t index) {
    __m512i z = _mm512_add_epi64(_mm512_mullo_epi64(key, set64(0x9E3779B97F4A7C15ull)), set64(index + 0x632BE59BD9B4E019ull));
    z = _mm512_mullo_epi64(_mm512_xor_si512(z, _mm512_srli_epi64(z, 30)), set64(0xBF58476D1CE4E5B9ull));
    z = _mm512_mullo_epi64(_mm512_xor_si512(z, _mm512_srli_epi64(z, 27)), set64(0x94D049BB133111EBull));
    return _mm512_xor_si512(z, _mm512_srli_epi64(z, 31));
}

/// The low and the high halves of eight 64-bit lanes, as eight 32-bit lanes.
SYMPHONG_LANES_TARGET __m256i low32(__m512i v) { return _mm512_cvtepi64_epi32(v); }
SYMPHONG_LANES_TARGET __m256i high32(__m512i v) { return _mm512_cvtepi64_epi32(_mm512_srli_epi64(v, 32)); }

/// reverseBits32 of eight lanes: each byte's bits mirrored by GFNI's affine map with the anti-diagonal
/// matrix, then the bytes of each lane reversed.
SYMPHONG_LANES_TARGET __m256i reverseBitsLanes(__m256i v) {
    v = _mm256_gf2p8affine_epi64_epi8(v, _mm256_set1_epi64x(0x8040201008040201ll), 0);
    const __m256i bytes =
        _mm256_setr_epi8(3, 2, 1, 0, 7, 6, 5, 4, 11, 10, 9, 8, 15, 14, 13, 12, 3, 2, 1, 0, 7, 6, 5, 4, 11, 10, 9, 8, 15, 14, 13, 12);
    return _mm256_shuffle_epi8(v, bytes);
}

/// detail::laineKarras of eight lanes.
SYMPHONG_LANES_TARGET __m256i laineKarrasLanes(__m256i v, __m256i seed) {
    v = _mm256_xor_si256(v, _mm256_mullo_epi32(v, set32(0x3d20adeau)));
    v = _mm256_add_epi32(v, seed);
    v = _mm256_mullo_epi32(v, _mm256_or_si256(_mm256_srli_epi32(seed, 16), set32(1u)));
    v = _mm256_xor_si256(v, _mm256_mullo_epi32(v, set32(0x05526c56u)));
    return _mm256_xor_si256(v, _mm256_mullo_epi32(v, set32(0x53a22864u)));
}

/// Entry i of a row of 16-bit table entries, for eight lanes: the 32-bit word that ends with entry i (its
/// upper half; the lower half is the entry before, or the previous row's last, which exists for every row
/// a caller passes) gathered and shifted down.
SYMPHONG_LANES_TARGET __m256i gather16(const std::uint16_t* row, __m256i i) {
    const void* base = reinterpret_cast<const char*>(row) - sizeof(std::uint16_t);
    return _mm256_srli_epi32(_mm256_i32gather_epi32(static_cast<const int*>(base), i, 2), 16);
}

/// permuteSamples(i, count, seed) of eight lanes for a count the lanes take (lanesTake): permutePowerOfTwo
/// with k = log2(count) >= 1, a = x^logA and b from the seed, i -> exp[log i + logA] ^ b (0 -> b).
SYMPHONG_LANES_TARGET __m256i permuteLanes(__m256i i, std::uint32_t count, __m256i seed) {
    if (count <= 1) return _mm256_setzero_si256();
    const std::uint32_t k = static_cast<std::uint32_t>(std::bit_width(count - 1));
    const std::uint32_t mask = (1u << k) - 1u;
    // logA = (seed x mask) >> 32 with the 64-bit product: vpmuludq of the zero-extended lanes.
    const __m512i product = _mm512_mul_epu32(_mm512_cvtepu32_epi64(seed), set64(mask));
    const __m256i logA = high32(product);
    const __m256i b = _mm256_srlv_epi32(_mm256_mullo_epi32(seed, set32(0x9E3779B9u)), set32(32 - k));
    i = _mm256_and_si256(i, set32(mask));
    const auto& t = detail::kGfTables;
    const __m256i logI = gather16(t.log[k], i);
    const __m256i image = gather16(t.exp[k], _mm256_add_epi32(logI, logA));
    const __mmask8 nonzero = _mm256_cmpneq_epi32_mask(i, _mm256_setzero_si256());
    return _mm256_xor_si256(_mm256_maskz_mov_epi32(nonzero, image), b);
}

/// fixedToUnit of eight lanes: exactly (double)v / 2^32.
SYMPHONG_LANES_TARGET __m512d unitLanes(__m256i v) { return _mm512_mul_pd(_mm512_cvtepu32_pd(v), _mm512_set1_pd(1.0 / 4294967296.0)); }

__attribute__((target("avx512f,avx512dq,avx512bw,avx512vl,gfni"))) void pairLanes(const std::uint64_t* keys, const std::uint32_t* indices,
                                                                                  std::uint32_t count, std::uint64_t dim, std::size_t n,
                                                                                  double* us, double* vs) {
    const auto& r = detail::kSobolDimension1Tables.reversed;
    for (std::size_t c = 0; c < n; c += 8) {
        const __mmask8 m = n - c >= 8 ? __mmask8(0xFF) : static_cast<__mmask8>((1u << (n - c)) - 1u);
        const __m512i h = mixSeedLanes(_mm512_maskz_loadu_epi64(m, keys + c), 2 * dim);
        // SobolSampler::pairPermutationSeed: the high half of h times an odd constant.
        const __m256i permutationSeed = high32(_mm512_mullo_epi64(h, set64(0xD6E8FEB86659FD93ull)));
        const __m256i j = permuteLanes(_mm256_maskz_loadu_epi32(m, indices + c), count, permutationSeed);
        // owenScrambledSobol0(j, low32(h)) and owenScrambledSobol1(j, high32(h)), j < 2^10.
        const __m256i u = reverseBitsLanes(laineKarrasLanes(j, low32(h)));
        const __m256i lowByte = _mm256_i32gather_epi32(reinterpret_cast<const int*>(r[0]), _mm256_and_si256(j, set32(0xFFu)), 4);
        const __m256i highByte = _mm256_i32gather_epi32(reinterpret_cast<const int*>(r[1]), _mm256_srli_epi32(j, 8), 4);
        const __m256i v = reverseBitsLanes(laineKarrasLanes(_mm256_xor_si256(lowByte, highByte), high32(h)));
        _mm512_mask_storeu_pd(us + c, m, unitLanes(u));
        _mm512_mask_storeu_pd(vs + c, m, unitLanes(v));
    }
}

__attribute__((target("avx512f,avx512dq,avx512bw,avx512vl,gfni"))) void singleLanes(const std::uint64_t* keys, const std::uint32_t* indices,
                                                                                    std::uint32_t count, std::uint64_t dim, std::size_t n,
                                                                                    double* out) {
    for (std::size_t c = 0; c < n; c += 8) {
        const __mmask8 m = n - c >= 8 ? __mmask8(0xFF) : static_cast<__mmask8>((1u << (n - c)) - 1u);
        const __m512i h = mixSeedLanes(_mm512_maskz_loadu_epi64(m, keys + c), 2 * dim + 1);
        const __m256i j = permuteLanes(_mm256_maskz_loadu_epi32(m, indices + c), count, high32(h));
        _mm512_mask_storeu_pd(out + c, m, unitLanes(reverseBitsLanes(laineKarrasLanes(j, low32(h)))));
    }
}

bool cpuHasLanes() {
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512bw") &&
           __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("gfni");
}

}  // namespace

bool sobolLanesAvailable() {
    static const bool available = cpuHasLanes();
    return available;
}

namespace detail {

void sobolPairValuesLanes(const std::uint64_t* keys, const std::uint32_t* indices, std::uint32_t count, std::uint64_t dim, std::size_t n,
                          double* us, double* vs) {
    if (lanesTake(count))
        pairLanes(keys, indices, count, dim, n, us, vs);
    else
        sobolPairValuesScalar(keys, indices, count, dim, n, us, vs);
}

void sobolSingleValuesLanes(const std::uint64_t* keys, const std::uint32_t* indices, std::uint32_t count, std::uint64_t dim, std::size_t n,
                            double* out) {
    if (lanesTake(count))
        singleLanes(keys, indices, count, dim, n, out);
    else
        sobolSingleValuesScalar(keys, indices, count, dim, n, out);
}

}  // namespace detail

#else  // no lanes on this target: the scalar forms

bool sobolLanesAvailable() { return false; }

namespace detail {
void sobolPairValuesLanes(const std::uint64_t* keys, const std::uint32_t* indices, std::uint32_t count, std::uint64_t dim, std::size_t n,
                          double* us, double* vs) {
    sobolPairValuesScalar(keys, indices, count, dim, n, us, vs);
}
void sobolSingleValuesLanes(const std::uint64_t* keys, const std::uint32_t* indices, std::uint32_t count, std::uint64_t dim, std::size_t n,
                            double* out) {
    sobolSingleValuesScalar(keys, indices, count, dim, n, out);
}
}  // namespace detail

#endif

void sobolPairValues(const std::uint64_t* keys, const std::uint32_t* indices, std::uint32_t count, std::uint64_t dim, std::size_t n,
                     double* us, double* vs) {
    if (sobolLanesAvailable())
        detail::sobolPairValuesLanes(keys, indices, count, dim, n, us, vs);
    else
        detail::sobolPairValuesScalar(keys, indices, count, dim, n, us, vs);
}

void sobolSingleValues(const std::uint64_t* keys, const std::uint32_t* indices, std::uint32_t count, std::uint64_t dim, std::size_t n,
                       double* out) {
    if (sobolLanesAvailable())
        detail::sobolSingleValuesLanes(keys, indices, count, dim, n, out);
    else
        detail::sobolSingleValuesScalar(keys, indices, count, dim, n, out);
}

}  // namespace symphong
