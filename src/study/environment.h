// study/ — measuring estimators: incoming-radiance environments with exact reflected radiance (this
// file), the single-point furnace that compares estimators under them (furnace.h), and, built on the
// renderer, the image-level studies. It owns no rendering or sampling code; it only drives and measures.
#pragma once

#include "math/vec3.h"

#include <string>
#include <vector>

namespace symphong {

/// The set { w : w . axis >= cosRadius } on the unit sphere.
struct SphericalCap {
    Vec3 axis;
    double cosRadius;
    bool contains(const Vec3& w) const { return dot(w, axis) >= cosRadius; }
};

/// Incoming radiance L(w) at one shading point, in its local frame (normal +Z): a smooth quadratic
/// c0 + c1 (w.g) + c2 (w.g)^2 inside the intersection of a few caps, zero outside. Every environment of
/// `symphong furnace --environment` is of this form, which is what lets exactReflected() integrate it to
/// round-off: the discontinuities are circles, handled analytically.
struct Environment {
    std::string name;
    std::string description;
    std::vector<SphericalCap> caps;
    double c0 = 1, c1 = 0, c2 = 0;
    Vec3 g{0, 0, 1};

    double radiance(const Vec3& w) const;
};

struct EnvironmentParams {
    double diskTheta = 30, diskPhi = 180, diskRadius = 10;  ///< degrees: disk light's direction and angular radius
    double bandDegrees = 15;                                ///< height of the horizon band
};

/// constant, gradient, disk, band, halfspace.
const std::vector<std::string>& environmentNames();
/// Throws std::invalid_argument naming the valid ones.
Environment makeEnvironment(const std::string& name, const EnvironmentParams& params = {});

/// Exact reflected radiance  int f(wo,w) L(w) max(0, w.z) dw  for the normalised Phong BRDF with grey
/// rho_d, rho_s and exponent n: the diffuse part integrated in the normal's frame, the specular part in
/// the lobe's frame with the substitution s = cos^(n+1)(alpha); rings of constant polar angle are cut by
/// the caps analytically and integrated by 32-point Gauss-Legendre, the polar angle by adaptive Simpson
/// split at every cap's tangency. Accurate to about 1e-9 relative.
double exactReflected(const Environment& env, double rhoD, double rhoS, double n, const Vec3& wo);

}  // namespace symphong
