#include "sampling/separation.h"

#include <algorithm>

namespace symphong::separation {

int octantOf(const Vec3& w) {
    double phi = std::atan2(w.y, w.x);
    if (phi < 0) phi += kTwoPi;
    return std::min(7, static_cast<int>(phi / (kPi / 4.0)));
}

Piece pieceOf(const Vec3& w) { return {inTriangles(w) ? PieceKind::Triangle : PieceKind::Quadrangle, octantOf(w)}; }

namespace {

Vec3 fromAngles(double theta, double phi) { return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)}; }

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

namespace {

constexpr double kInvSqrt2 = 0.70710678118654752440;

/// The direction above the unit-disk point at rho^2 and azimuth phi = atan(t), phi in [0, pi/4]:
/// cos(phi) = 1/sqrt(1+t^2), sin(phi) = t cos(phi), no trigonometry.
Vec3 fromDiskTangent(double rho2, double t) {
    const double c = 1.0 / std::sqrt(1.0 + t * t), rho = std::sqrt(rho2);
    return {rho * c, rho * t * c, std::sqrt(std::max(0.0, 1.0 - rho2))};
}

/// rho_T^2 from t = tan(phi): 1/(1 + cos^2 phi) = (1 + t^2)/(2 + t^2).
double triangleEdgeRho2FromTangent(double t) { return (1.0 + t * t) / (2.0 + t * t); }

/// The quadrangle's area up to phi = atan(t), G as a function of t:
///   H(t) = (atan t - atan(t/sqrt 2)/sqrt 2) / 2,   H'(t) = 1 / (2 (1 + t^2) (2 + t^2)).
double quadrangleArea(double t) { return 0.5 * (std::atan(t) - std::atan(t * kInvSqrt2) * kInvSqrt2); }
double quadrangleAreaSlope(double t) { return 0.5 / ((1.0 + t * t) * (2.0 + t * t)); }

/// Cubic Hermite table of H^-1 on [0, Phi_Q]: values and slopes 1/H' at 256 + 1 knots, each knot solved
/// by bisection to round-off. Its error is below 4e-10 (measured), so one Newton step reaches round-off.
struct QuadrangleInverse {
    static constexpr int kKnots = 256;
    double t[kKnots + 1], slope[kKnots + 1];
    QuadrangleInverse() {
        for (int i = 0; i <= kKnots; ++i) {
            const double area = kQuadrangleProjected * i / kKnots;
            double lo = 0, hi = 1;
            for (int k = 0; k < 200; ++k) {
                const double mid = 0.5 * (lo + hi);
                if (mid <= lo || mid >= hi) break;
                (quadrangleArea(mid) < area ? lo : hi) = mid;
            }
            t[i] = i == 0 ? 0.0 : i == kKnots ? 1.0 : 0.5 * (lo + hi);
            slope[i] = (kQuadrangleProjected / kKnots) / quadrangleAreaSlope(t[i]);
        }
    }
    double operator()(double area) const {
        const double x = std::clamp(area / kQuadrangleProjected, 0.0, 1.0) * kKnots;
        const int i = std::min(kKnots - 1, static_cast<int>(x));
        const double s = x - i, s2 = s * s, s3 = s2 * s;
        return (2 * s3 - 3 * s2 + 1) * t[i] + (s3 - 2 * s2 + s) * slope[i] + (3 * s2 - 2 * s3) * t[i + 1] + (s3 - s2) * slope[i + 1];
    }
};

}  // namespace

// phi = atan(sqrt(2) tan(u kA)); with t = tan(phi) everything after it is algebraic.
Vec3 triangleMap(Point2 p) {
    const double t = std::sqrt(2.0) * std::tan(p.u * kA);
    return fromDiskTangent(p.v * triangleEdgeRho2FromTangent(t), t);
}

double quadrangleTangent(double area) {
    static const QuadrangleInverse inverse;
    const double t = inverse(area);
    // One Newton step on H(t) = area from the table's guess (error < 4e-10 -> ~1e-19).
    return std::clamp(t - (quadrangleArea(t) - area) / quadrangleAreaSlope(t), 0.0, 1.0);
}

double quadrangleAzimuth(double area) { return std::atan(quadrangleTangent(area)); }

Vec3 quadrangleMap(Point2 p) {
    const double t = quadrangleTangent(p.u * kQuadrangleProjected);
    const double r2 = triangleEdgeRho2FromTangent(t);
    return fromDiskTangent(r2 + p.v * (1.0 - r2), t);
}

Vec3 octantCosineMap(Point2 p) {
    if (p.u < kTriangleShare) return triangleMap({std::min(p.u / kTriangleShare, kOneBelow), p.v});
    return quadrangleMap({std::min((p.u - kTriangleShare) / (1.0 - kTriangleShare), kOneBelow), p.v});
}

Vec3 phongWedgeMap(Point2 p, double n) {
    const double phi = p.u * kPi / 4.0;
    // cos(alpha) = v^(1/(n+1)); sin(alpha) = sqrt((1 - cos)(1 + cos)), which keeps its relative precision
    // near the axis (1 - cos is exact for cos in [1/2, 1], Sterbenz).
    const double cosA = std::pow(p.v, 1.0 / (n + 1.0));
    const double sinA = std::sqrt(std::max(0.0, (1.0 - cosA) * (1.0 + cosA)));
    return {sinA * std::cos(phi), sinA * std::sin(phi), cosA};
}

namespace {

/// c(phi) = 1 - (cos^2 phi / (1 + cos^2 phi))^((n+1)/2): the lobe's share inside the triangle at phi,
/// from c2 = cos^2(phi).
/// c2 / (1 + c2) <= 1/2 and (n+1)/2 >= 1/2, so the power is at most 0.71: no cancellation in 1 - pow.
double lobeEdgeMass(double c2, double n) { return 1.0 - std::pow(c2 / (1.0 + c2), 0.5 * (n + 1.0)); }

}  // namespace

Vec3 lobeTriangleMap(Point2 p, double n) {
    const double phi = p.u * kPi / 4.0;
    const double cosPhi = std::cos(phi), sinPhi = std::sin(phi);
    const double c = lobeEdgeMass(cosPhi * cosPhi, n);
    // s^2 = (1 - v c)^(-2/(n+1)) - 1, written with log1p/expm1 so large n keeps its precision.
    const double s2 = std::expm1(-2.0 / (n + 1.0) * std::log1p(-p.v * c));
    const double s = std::sqrt(std::max(0.0, s2));
    const double inv = 1.0 / std::sqrt(1.0 + s * s);
    return {s * cosPhi * inv, s * sinPhi * inv, inv};
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
