// sampling/warp_lanes.h — warps of warp.h for many points at once, the same directions bit for bit: where the
// processor has AVX-512 (F, checked at run time), eight points a step in vector lanes, else one at a time by
// warp.h's own functions. The lanes do the scalar warp's operations in its order, each of them (+, -, x, /,
// square root, the comparisons and choices) correctly rounded in a lane as in a register; no fused
// multiply-adds (warp_lanes.cpp is compiled with -ffp-contract=off, as x86-64's baseline code has none). The
// wavefront tracer's estimator draws a depth's diffuse directions here (estimators/basic.cpp drawAhead);
// docs/performance.md "Directions in vector lanes" has what it saves.
#pragma once

#include "math/vec3.h"

#include <cstddef>

namespace symphong {

/// out[i] = sampleCosineHemisphere({us[i], vs[i]}), i < n.
void cosineHemisphereDirections(const double* us, const double* vs, std::size_t n, Vec3* out);
/// Whether the call above runs in vector lanes on this processor (AVX-512 F).
bool warpLanesAvailable();

namespace detail {
/// The two forms, for tests: one point at a time, and the lanes (only where warpLanesAvailable()).
void cosineHemisphereDirectionsScalar(const double* us, const double* vs, std::size_t n, Vec3* out);
void cosineHemisphereDirectionsLanes(const double* us, const double* vs, std::size_t n, Vec3* out);
}  // namespace detail

}  // namespace symphong
