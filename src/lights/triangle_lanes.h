// lights/triangle_lanes.h — sampleTriangleLight (lights/kinds.h) for many shading points at once, each towards
// its own emissive triangle, the same samples bit for bit: where the processor has AVX-512 (F, checked at run
// time), eight a step in vector lanes (the point on the triangle, the direction's square root and divisions,
// the density), else one at a time by sampleTriangleLight itself. Only triangles without textures (whose
// emission and cut-outs need no look-up). As in sampling/warp_lanes.h, the lanes do the scalar function's
// operations in its order, each rounded alone (triangle_lanes.cpp is compiled with -ffp-contract=off). The
// wavefront tracer draws a depth's light samples here through SceneEmitters::sampleMany.
#pragma once

#include "lights/kinds.h"

#include <cstddef>
#include <cstdint>

namespace symphong {

/// The rows the lanes take: their starts in doubles are 32-bit gather indices.
constexpr std::size_t kTriangleLaneRows = (std::size_t{1} << 31) / (sizeof(TriangleLight) / sizeof(double)) - 1;

/// sampled[i] = sampleTriangleLight(table[rows[i]], scene, ps[i], {us[i], vs[i]}, out[i]), i < n; every row's
/// light untextured, every row below kTriangleLaneRows. Where sampled[i] is false, out[i] is unspecified (as
/// sampleTriangleLight leaves it).
void sampleTriangleLights(const TriangleLight* table, const std::uint32_t* rows, const Scene& scene, const Vec3* ps, const double* us,
                          const double* vs, std::size_t n, EmitterSample* out, bool* sampled);
/// Whether the call above runs in vector lanes on this processor (AVX-512 F).
bool triangleLanesAvailable();

namespace detail {
/// The two forms, for tests: one sample at a time, and the lanes (only where triangleLanesAvailable()).
void sampleTriangleLightsScalar(const TriangleLight* table, const std::uint32_t* rows, const Scene& scene, const Vec3* ps, const double* us,
                                const double* vs, std::size_t n, EmitterSample* out, bool* sampled);
void sampleTriangleLightsLanes(const TriangleLight* table, const std::uint32_t* rows, const Scene& scene, const Vec3* ps, const double* us,
                               const double* vs, std::size_t n, EmitterSample* out, bool* sampled);
}  // namespace detail

}  // namespace symphong
