// sampling/warp.h — warps from the unit square to the hemisphere (normal = +Z), to the Phong lobe and
// to triangles, each with its density. Solid-angle densities unless stated otherwise.
#pragma once

#include "math/branchless.h"
#include "math/trig.h"
#include "math/vec3.h"
#include "sampling/rng.h"

#include <cmath>

namespace symphong {

/// Direction from spherical angles: (sin t cos p, sin t sin p, cos t).
inline Vec3 sphericalDirection(double cosTheta, double phi) {
    const double sinTheta = std::sqrt(std::max(0.0, 1.0 - cosTheta * cosTheta));
    return {sinTheta * std::cos(phi), sinTheta * std::sin(phi), cosTheta};
}
/// The same with phi = 2 pi v (v in [0, 1]), its sine and cosine by math/trig.h sinCosTurn: what the
/// warps below draw.
inline Vec3 sphericalDirectionTurn(double cosTheta, double v) {
    const double sinTheta = std::sqrt(std::max(0.0, 1.0 - cosTheta * cosTheta));
    const SinCos phi = sinCosTurn(v);
    return {sinTheta * phi.cos, sinTheta * phi.sin, cosTheta};
}

/// Uniform hemisphere: cos(theta) = u, phi = 2 pi v.  p(w) = 1 / (2 pi).
inline Vec3 sampleUniformHemisphere(Point2 p) { return sphericalDirectionTurn(p.u, p.v); }
inline double uniformHemispherePdf(const Vec3& w) { return w.z > 0 ? 1.0 / kTwoPi : 0.0; }

/// Shirley-Chiu concentric map of [0,1)^2 onto the unit disk; area-preserving up to the factor pi,
/// and continuous, so strata of the square stay compact on the disk.
inline Point2 sampleConcentricDisk(Point2 p) {
    const double a = 2.0 * p.u - 1.0, b = 2.0 * p.v - 1.0;
    if (a == 0 && b == 0) return {0, 0};
    // phi = pi/4 (b/a) when |a| > |b| (the point is r = a along x, at t = pi/4 (b/a) from it), else
    // pi/2 - pi/4 (a/b) (r = b along y, t = pi/4 (a/b) from it towards x): (r cos t, r sin t) with its
    // coordinates exchanged in the second case. Which case holds is a coin toss per sample: chosen by
    // masks, not a branch (math/branchless.h).
    const bool alongX = std::abs(a) > std::abs(b);
    const double r = choose(alongX, a, b), other = choose(alongX, b, a);
    const SinCos t = sinCosQuarter((kPi / 4.0) * (other / r));
    const double along = r * t.cos, across = r * t.sin;
    return {choose(alongX, along, across), choose(alongX, across, along)};
}

/// Cosine-weighted hemisphere (Malley: project the concentric disk up).  p(w) = cos(theta) / pi.
inline Vec3 sampleCosineHemisphere(Point2 p) {
    const Point2 d = sampleConcentricDisk(p);
    const double z = std::sqrt(std::max(0.0, 1.0 - d.u * d.u - d.v * d.v));
    return {d.u, d.v, z};
}
inline double cosineHemispherePdf(const Vec3& w) { return w.z > 0 ? w.z * kInvPi : 0.0; }

/// Phong lobe around +Z: cos(alpha) = u^(1/(n+1)), phi = 2 pi v.  p(w) = (n+1)/(2 pi) cos^n(alpha),
/// over the whole sphere's upper cap around the axis (alpha in [0, pi/2]).
inline Vec3 samplePhongLobe(Point2 p, double n) { return sphericalDirectionTurn(std::pow(p.u, 1.0 / (n + 1.0)), p.v); }
inline double phongLobePdf(double cosAlpha, double n) { return cosAlpha > 0 ? (n + 1.0) / kTwoPi * std::pow(cosAlpha, n) : 0.0; }

/// Uniform point on a triangle as barycentrics (b0, b1); b2 = 1 - b0 - b1.  p = 1 / area.
/// b0 = 1 - sqrt(u), b1 = v sqrt(u)  (Shirley and Chiu; pbrt-v3 UniformSampleTriangle).
inline Point2 sampleUniformTriangle(Point2 p) {
    const double su = std::sqrt(p.u);
    return {1.0 - su, p.v * su};
}

/// Jittered point in cell (i, j) of an nx x ny grid over [0,1)^2.
inline Point2 jitterInStratum(int i, int j, int nx, int ny, Point2 jitter) { return {(i + jitter.u) / nx, (j + jitter.v) / ny}; }

}  // namespace symphong
