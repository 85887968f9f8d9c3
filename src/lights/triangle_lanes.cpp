// Triangle light samples in lanes (triangle_lanes.h): sampleTriangleLight and sampleUniformTriangle of
// triangle_emitter.cpp and sampling/warp.h step by step, eight samples a vector.
#include "lights/triangle_lanes.h"

#include "sampling/x86_lanes.h"

#include <cstddef>
#include <cstdint>

namespace symphong {

namespace detail {

void sampleTriangleLightsScalar(const TriangleLight* table, const std::uint32_t* rows, const Scene& scene, const Vec3* ps, const double* us,
                                const double* vs, std::size_t n, EmitterSample* out, bool* sampled) {
    for (std::size_t i = 0; i < n; ++i) sampled[i] = sampleTriangleLight(table[rows[i]], scene, ps[i], {us[i], vs[i]}, out[i]);
}

}  // namespace detail

#ifdef SYMPHONG_X86_LANES

namespace {

#define SYMPHONG_TRIANGLE_TARGET __attribute__((target("avx512f"), always_inline)) inline

/// A double of each lane's triangle light: `field` bytes into its row of the table (the rows' indices in units of
/// doubles, as the gather scales them).
SYMPHONG_TRIANGLE_TARGET __m512d gatherField(const TriangleLight* table, __m256i rowStarts, std::size_t field) {
    return _mm512_i32gather_pd(_mm256_add_epi32(rowStarts, _mm256_set1_epi32(static_cast<int>(field / sizeof(double)))), table,
                               sizeof(double));
}

/// Coordinate `axis` of the eight lanes' triangle light's Vec3 `field`.
SYMPHONG_TRIANGLE_TARGET __m512d gatherAxis(const TriangleLight* table, __m256i rowStarts, std::size_t field, int axis) {
    return gatherField(table, rowStarts, field + static_cast<std::size_t>(axis) * sizeof(double));
}

__attribute__((target("avx512f"))) void triangleLanes(const TriangleLight* table, const std::uint32_t* rows, const Vec3* ps,
                                                      const double* us, const double* vs, std::size_t n, EmitterSample* out,
                                                      bool* sampled) {
    static_assert(sizeof(TriangleLight) % sizeof(double) == 0 && sizeof(Vec3) == 3 * sizeof(double), "rows gathered in doubles");
    const __m512d one = _mm512_set1_pd(1.0), zero = _mm512_setzero_pd();
    const __m512i signBit = _mm512_set1_epi64(static_cast<long long>(0x8000000000000000ull));
    const __m256i rowLength = _mm256_set1_epi32(static_cast<int>(sizeof(TriangleLight) / sizeof(double)));
    const __m256i allPoints = _mm256_setr_epi32(0, 3, 6, 9, 12, 15, 18, 21);  // lane k's point: doubles 3k, 3k + 1, 3k + 2
    for (std::size_t c = 0; c < n; c += 8) {
        const std::size_t lanes = n - c >= 8 ? 8 : n - c;
        const __mmask8 m = static_cast<__mmask8>((1u << lanes) - 1u);
        __m256i laneRows = _mm256_setzero_si256(), pointStarts = allPoints;
        if (lanes == 8) {
            laneRows = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(rows + c));
        } else {  // the lanes past n read row 0 and the first point (gathers of all eight, their results unused)
            alignas(32) std::int32_t partRows[8] = {}, partPoints[8] = {};
            for (std::size_t k = 0; k < lanes; ++k) {
                partRows[k] = static_cast<std::int32_t>(rows[c + k]);
                partPoints[k] = static_cast<std::int32_t>(3 * k);
            }
            laneRows = _mm256_load_si256(reinterpret_cast<const __m256i*>(partRows));
            pointStarts = _mm256_load_si256(reinterpret_cast<const __m256i*>(partPoints));
        }
        const __m256i rowStarts = _mm256_mullo_epi32(laneRows, rowLength);
        const auto* point = reinterpret_cast<const double*>(ps + c);
        // sampleUniformTriangle: b0 = 1 - sqrt(u), b1 = v sqrt(u); q = v0 b0 + v1 b1 + v2 ((1 - b0) - b1).
        const __m512d su = _mm512_sqrt_pd(_mm512_maskz_loadu_pd(m, us + c));
        const __m512d b0 = _mm512_sub_pd(one, su), b1 = _mm512_mul_pd(_mm512_maskz_loadu_pd(m, vs + c), su);
        const __m512d b2 = _mm512_sub_pd(_mm512_sub_pd(one, b0), b1);
        __m512d q[3], to[3];
        for (int a = 0; a < 3; ++a) {
            const __m512d v0 = gatherAxis(table, rowStarts, offsetof(TriangleLight, v0), a);
            const __m512d v1 = gatherAxis(table, rowStarts, offsetof(TriangleLight, v1), a);
            const __m512d v2 = gatherAxis(table, rowStarts, offsetof(TriangleLight, v2), a);
            q[a] = _mm512_add_pd(_mm512_add_pd(_mm512_mul_pd(v0, b0), _mm512_mul_pd(v1, b1)), _mm512_mul_pd(v2, b2));
            const __m512d p = _mm512_i32gather_pd(_mm256_add_epi32(pointStarts, _mm256_set1_epi32(a)), point, sizeof(double));
            to[a] = _mm512_sub_pd(q[a], p);
        }
        // dist2 = to . to; wi = to x (1 / sqrt(dist2)); cosL = -(normal . wi); pdf = (pick / area x dist2) / cosL.
        const __m512d dist2 =
            _mm512_add_pd(_mm512_add_pd(_mm512_mul_pd(to[0], to[0]), _mm512_mul_pd(to[1], to[1])), _mm512_mul_pd(to[2], to[2]));
        const __m512d inverse = _mm512_div_pd(one, _mm512_sqrt_pd(dist2));
        __m512d wi[3], facing = zero;
        for (int a = 0; a < 3; ++a) {
            wi[a] = _mm512_mul_pd(to[a], inverse);
            const __m512d term = _mm512_mul_pd(gatherAxis(table, rowStarts, offsetof(TriangleLight, normal), a), wi[a]);
            facing = a == 0 ? term : _mm512_add_pd(facing, term);
        }
        const __m512d cosL = _mm512_castsi512_pd(_mm512_xor_si512(_mm512_castpd_si512(facing), signBit));  // -(normal . wi)
        const __m512d pdf = _mm512_div_pd(_mm512_mul_pd(gatherField(table, rowStarts, offsetof(TriangleLight, pickOverArea)), dist2), cosL);
        // sampleTriangleLight's tests, dist2 <= 0 and cosL <= 0, false for a NaN as there.
        const __mmask8 ok = _mm512_cmp_pd_mask(dist2, zero, _CMP_NLE_UQ) & _mm512_cmp_pd_mask(cosL, zero, _CMP_NLE_UQ);
        alignas(64) double results[7][8];
        for (int a = 0; a < 3; ++a) {
            _mm512_store_pd(results[a], wi[a]);
            _mm512_store_pd(results[3 + a], q[a]);
        }
        _mm512_store_pd(results[6], pdf);
        for (std::size_t k = 0; k < lanes; ++k) {
            EmitterSample& s = out[c + k];
            sampled[c + k] = (ok >> k) & 1u;
            s.wi = {results[0][k], results[1][k], results[2][k]};
            s.pdf = results[6][k];
            s.target = {results[3][k], results[4][k], results[5][k]};
            s.toInfinity = false;
            s.delta = false;
            s.radianceLater = false;
            s.radiance = table[rows[c + k]].emission;
        }
    }
}

}  // namespace

bool triangleLanesAvailable() { return avx512fAvailable(); }

namespace detail {
void sampleTriangleLightsLanes(const TriangleLight* table, const std::uint32_t* rows, const Scene&, const Vec3* ps, const double* us,
                               const double* vs, std::size_t n, EmitterSample* out, bool* sampled) {
    triangleLanes(table, rows, ps, us, vs, n, out, sampled);
}
}  // namespace detail

#else  // no lanes on this target: the scalar form

bool triangleLanesAvailable() { return false; }

namespace detail {
void sampleTriangleLightsLanes(const TriangleLight* table, const std::uint32_t* rows, const Scene& scene, const Vec3* ps, const double* us,
                               const double* vs, std::size_t n, EmitterSample* out, bool* sampled) {
    sampleTriangleLightsScalar(table, rows, scene, ps, us, vs, n, out, sampled);
}
}  // namespace detail

#endif

void sampleTriangleLights(const TriangleLight* table, const std::uint32_t* rows, const Scene& scene, const Vec3* ps, const double* us,
                          const double* vs, std::size_t n, EmitterSample* out, bool* sampled) {
    if (triangleLanesAvailable())
        detail::sampleTriangleLightsLanes(table, rows, scene, ps, us, vs, n, out, sampled);
    else
        detail::sampleTriangleLightsScalar(table, rows, scene, ps, us, vs, n, out, sampled);
}

}  // namespace symphong
