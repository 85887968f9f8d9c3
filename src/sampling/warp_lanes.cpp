// Warps in lanes (warp_lanes.h): sampleConcentricDisk, sinCosQuarter and sampleCosineHemisphere of warp.h and
// math/trig.h step by step, eight points a vector.
#include "sampling/warp_lanes.h"

#include "sampling/warp.h"
#include "sampling/x86_lanes.h"

namespace symphong {

namespace detail {

void cosineHemisphereDirectionsScalar(const double* us, const double* vs, std::size_t n, Vec3* out) {
    for (std::size_t i = 0; i < n; ++i) out[i] = sampleCosineHemisphere({us[i], vs[i]});
}

}  // namespace detail

#ifdef SYMPHONG_X86_LANES

namespace {

#define SYMPHONG_WARP_TARGET __attribute__((target("avx512f"), always_inline)) inline

SYMPHONG_WARP_TARGET __m512d set(double v) { return _mm512_set1_pd(v); }

/// sinCosQuarter's chains, from the innermost term out: each step x2 * (term + the step before), as math/trig.h
/// nests them; the sine's chain ends in x * (1 + ...), the cosine's in 1 + ....
constexpr double kSinTerms[] = {
    1.0 / 355687428096000.0, -1.0 / 1307674368000.0, 1.0 / 6227020800.0, -1.0 / 39916800, 1.0 / 362880, -1.0 / 5040, 1.0 / 120, -1.0 / 6};
constexpr double kCosTerms[] = {
    1.0 / 20922789888000.0, -1.0 / 87178291200.0, 1.0 / 479001600.0, -1.0 / 3628800, 1.0 / 40320, -1.0 / 720, 1.0 / 24, -0.5};

SYMPHONG_WARP_TARGET __m512d hornerChain(__m512d x2, const double (&terms)[8]) {
    __m512d t = _mm512_mul_pd(x2, set(terms[0]));
    for (int k = 1; k < 8; ++k) t = _mm512_mul_pd(x2, _mm512_add_pd(set(terms[k]), t));
    return t;
}

/// sinCosQuarter of eight angles.
SYMPHONG_WARP_TARGET void sinCosQuarterLanes(__m512d x, __m512d& s, __m512d& c) {
    const __m512d x2 = _mm512_mul_pd(x, x);
    s = _mm512_mul_pd(x, _mm512_add_pd(set(1.0), hornerChain(x2, kSinTerms)));
    c = _mm512_add_pd(set(1.0), hornerChain(x2, kCosTerms));
}

__attribute__((target("avx512f"))) void cosineLanes(const double* us, const double* vs, std::size_t n, Vec3* out) {
    const __m512d one = set(1.0), two = set(2.0), zero = _mm512_setzero_pd();
    const __m512i signBit = _mm512_set1_epi64(static_cast<long long>(0x8000000000000000ull));
    for (std::size_t c = 0; c < n; c += 8) {
        const __mmask8 m = n - c >= 8 ? __mmask8(0xFF) : static_cast<__mmask8>((1u << (n - c)) - 1u);
        // sampleConcentricDisk: a = 2u - 1, b = 2v - 1; the centre (a = b = 0) maps to (0, 0).
        const __m512d a = _mm512_sub_pd(_mm512_mul_pd(two, _mm512_maskz_loadu_pd(m, us + c)), one);
        const __m512d b = _mm512_sub_pd(_mm512_mul_pd(two, _mm512_maskz_loadu_pd(m, vs + c)), one);
        const __mmask8 centre = _mm512_cmp_pd_mask(a, zero, _CMP_EQ_OQ) & _mm512_cmp_pd_mask(b, zero, _CMP_EQ_OQ);
        const __m512d absA = _mm512_castsi512_pd(_mm512_andnot_si512(signBit, _mm512_castpd_si512(a)));
        const __m512d absB = _mm512_castsi512_pd(_mm512_andnot_si512(signBit, _mm512_castpd_si512(b)));
        const __mmask8 alongX = _mm512_cmp_pd_mask(absA, absB, _CMP_GT_OQ);
        const __m512d r = _mm512_mask_blend_pd(alongX, b, a), other = _mm512_mask_blend_pd(alongX, a, b);
        __m512d sinT, cosT;
        sinCosQuarterLanes(_mm512_mul_pd(set(kPi / 4.0), _mm512_div_pd(other, r)), sinT, cosT);
        const __m512d along = _mm512_mul_pd(r, cosT), across = _mm512_mul_pd(r, sinT);
        const __m512d x = _mm512_maskz_mov_pd(static_cast<__mmask8>(~centre), _mm512_mask_blend_pd(alongX, across, along));
        const __m512d y = _mm512_maskz_mov_pd(static_cast<__mmask8>(~centre), _mm512_mask_blend_pd(alongX, along, across));
        // sampleCosineHemisphere: z = sqrt(max(0, 1 - x^2 - y^2)); max(t, 0) is t where t > 0, else 0, as
        // std::max(0.0, t) gives it.
        const __m512d t = _mm512_sub_pd(_mm512_sub_pd(one, _mm512_mul_pd(x, x)), _mm512_mul_pd(y, y));
        const __m512d z = _mm512_sqrt_pd(_mm512_max_pd(t, zero));
        alignas(64) double xs[8], ys[8], zs[8];
        _mm512_store_pd(xs, x);
        _mm512_store_pd(ys, y);
        _mm512_store_pd(zs, z);
        const std::size_t lanes = n - c >= 8 ? 8 : n - c;
        for (std::size_t k = 0; k < lanes; ++k) out[c + k] = {xs[k], ys[k], zs[k]};
    }
}

}  // namespace

bool warpLanesAvailable() { return avx512fAvailable(); }

namespace detail {
void cosineHemisphereDirectionsLanes(const double* us, const double* vs, std::size_t n, Vec3* out) { cosineLanes(us, vs, n, out); }
}  // namespace detail

#else  // no lanes on this target: the scalar form

bool warpLanesAvailable() { return false; }

namespace detail {
void cosineHemisphereDirectionsLanes(const double* us, const double* vs, std::size_t n, Vec3* out) {
    cosineHemisphereDirectionsScalar(us, vs, n, out);
}
}  // namespace detail

#endif

void cosineHemisphereDirections(const double* us, const double* vs, std::size_t n, Vec3* out) {
    if (warpLanesAvailable())
        detail::cosineHemisphereDirectionsLanes(us, vs, n, out);
    else
        detail::cosineHemisphereDirectionsScalar(us, vs, n, out);
}

}  // namespace symphong
