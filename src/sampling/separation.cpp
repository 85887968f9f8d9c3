#include "sampling/separation.h"

#include <algorithm>

namespace symphong::separation {

int octantOf(const Vec3& w) {
    double phi = std::atan2(w.y, w.x);
    if (phi < 0) phi += kTwoPi;
    return std::min(7, static_cast<int>(phi / (kPi / 4.0)));
}

Piece pieceOf(const Vec3& w) {
    return {inTriangles(w) ? PieceKind::Triangle : PieceKind::Quadrangle, octantOf(w)};
}

namespace {

Vec3 fromAngles(double theta, double phi) {
    return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

/// Direction above the unit-disk point rho (cos phi, sin phi).
Vec3 fromDisk(double rho2, double phi) {
    const double rho = std::sqrt(rho2);
    return {rho * std::cos(phi), rho * std::sin(phi), std::sqrt(std::max(0.0, 1.0 - rho2))};
}

}  // namespace

Vec3 paperTriangleMap(Point2 p) {
    const double phi = p.u * kPi / 4.0;
    return fromAngles(std::atan(p.v / std::cos(phi)), phi);
}

Vec3 paperQuadrangleMap(Point2 p) {
    const double phi = p.u * kPi / 4.0;
    return fromAngles(std::atan2(std::cos(phi), p.v), phi);  // arccot(x) = atan(1/x), x = v / cos(phi)
}

double paperWeight(Point2 p) {
    const double c = std::cos(p.u * kPi / 4.0), c2 = c * c;
    const double d = p.v * p.v + c2;
    return p.v * c2 / (d * d);
}

Vec3 triangleMap(Point2 p) {
    const double phi = std::atan(std::sqrt(2.0) * std::tan(p.u * kA));
    return fromDisk(p.v * triangleEdgeRho2(phi), phi);
}

double quadrangleAzimuth(double area) {
    // G(phi) = (phi - atan(tan(phi)/sqrt 2)/sqrt 2) / 2, increasing, G'(phi) = cos^2/(2 (1 + cos^2)) in [1/6, 1/4]:
    // Newton's method converges in a few steps; a bisection bracket guards it.
    const auto G = [](double phi) { return 0.5 * (phi - std::atan(std::tan(phi) / std::sqrt(2.0)) / std::sqrt(2.0)); };
    double lo = 0, hi = kPi / 4.0;
    double phi = std::clamp(area / kQuadrangleProjected * (kPi / 4.0), lo, hi);
    for (int i = 0; i < 50; ++i) {
        const double g = G(phi) - area;
        const double c2 = std::cos(phi) * std::cos(phi);
        const double step = g / (0.5 * c2 / (1.0 + c2));
        if (std::abs(step) <= 1e-15) return std::clamp(phi - step, 0.0, kPi / 4.0);
        if (g > 0) hi = phi; else lo = phi;
        phi -= step;
        if (!(phi > lo && phi < hi)) phi = 0.5 * (lo + hi);
    }
    return phi;
}

Vec3 quadrangleMap(Point2 p) {
    const double phi = quadrangleAzimuth(p.u * kQuadrangleProjected);
    const double r2 = triangleEdgeRho2(phi);
    return fromDisk(r2 + p.v * (1.0 - r2), phi);
}

namespace {

/// c(phi) = 1 - (cos^2 phi / (1 + cos^2 phi))^((n+1)/2): the lobe's share inside the triangle at phi,
/// from c2 = cos^2(phi).
double lobeEdgeMass(double c2, double n) { return -std::expm1(0.5 * (n + 1.0) * std::log(c2 / (1.0 + c2))); }

}  // namespace

Vec3 lobeTriangleMap(Point2 p, double n) {
    const double phi = p.u * kPi / 4.0;
    const double c = lobeEdgeMass(std::cos(phi) * std::cos(phi), n);
    // s^2 = (1 - v c)^(-2/(n+1)) - 1, written with log1p/expm1 so large n keeps its precision.
    const double s2 = std::expm1(-2.0 / (n + 1.0) * std::log1p(-p.v * c));
    const double s = std::sqrt(std::max(0.0, s2));
    const double inv = 1.0 / std::sqrt(1.0 + s * s);
    return {s * std::cos(phi) * inv, s * std::sin(phi) * inv, inv};
}

double lobeTriangleDensity(const Vec3& w, double n) {
    if (w.z <= 0) return 0.0;
    const double h2 = w.x * w.x + w.y * w.y;
    const double c2 = h2 > 0 ? w.x * w.x / h2 : 1.0;  // cos^2(phi) without trigonometry
    return 4.0 / kPi * (n + 1.0) * std::pow(w.z, n) / lobeEdgeMass(c2, n);
}

LobeFrame LobeFrame::fromMirror(const Vec3& r) {
    LobeFrame f;
    const double h = std::sqrt(r.x * r.x + r.y * r.y);
    f.cosS = r.z;
    f.sinS = h;
    if (h < 1e-12) {
        f.ex = {1, 0, 0};
        f.ey = {0, 1, 0};
        f.sinS = 0;
        f.cosS = 1;
    } else {
        f.ey = {-r.x / h, -r.y / h, 0};  // r = -sin(theta_s) ey + cos(theta_s) Z
        f.ex = cross(f.ey, Vec3(0, 0, 1));
    }
    return f;
}

Vec3 LobeFrame::toLocal(const Vec3& d) const {
    const double X = d.x, Y = d.y * cosS - d.z * sinS, Z = d.z * cosS + d.y * sinS;
    return ex * X + ey * Y + Vec3(0, 0, Z);
}

Vec3 LobeFrame::toFace(const Vec3& w) const {
    const double X = dot(w, ex), Y = dot(w, ey), Z = w.z;
    return {X, Y * cosS + Z * sinS, Z * cosS - Y * sinS};
}

}  // namespace symphong::separation
