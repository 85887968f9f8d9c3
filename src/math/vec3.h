// math/ — the small value types every other layer is written in: 3-vectors (also used as linear RGB
// colours), orthonormal frames and constants. Shading math is done in double precision so that the
// statistical tests (furnace, chi-square) measure the estimators, not round-off; geometry handed to
// Embree is converted to float at the accel/ boundary.
#pragma once

#include <algorithm>
#include <cmath>

namespace symphong {

inline constexpr double kPi = 3.14159265358979323846;
inline constexpr double kInvPi = 1.0 / kPi;
inline constexpr double kTwoPi = 2.0 * kPi;

struct Vec3 {
    double x = 0, y = 0, z = 0;

    constexpr Vec3() = default;
    constexpr Vec3(double x_, double y_, double z_) : x(x_), y(y_), z(z_) {}
    constexpr explicit Vec3(double s) : x(s), y(s), z(s) {}

    constexpr double operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
    constexpr double& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }

    constexpr Vec3 operator-() const { return {-x, -y, -z}; }
    constexpr Vec3& operator+=(const Vec3& o) {
        x += o.x;
        y += o.y;
        z += o.z;
        return *this;
    }
    constexpr Vec3& operator-=(const Vec3& o) {
        x -= o.x;
        y -= o.y;
        z -= o.z;
        return *this;
    }
    constexpr Vec3& operator*=(const Vec3& o) {
        x *= o.x;
        y *= o.y;
        z *= o.z;
        return *this;
    }
    constexpr Vec3& operator*=(double s) {
        x *= s;
        y *= s;
        z *= s;
        return *this;
    }
    constexpr Vec3& operator/=(double s) { return *this *= (1.0 / s); }
};

/// Linear RGB radiance or reflectance; one name for the role, the same type.
using Color = Vec3;

constexpr Vec3 operator+(Vec3 a, const Vec3& b) { return a += b; }
constexpr Vec3 operator-(Vec3 a, const Vec3& b) { return a -= b; }
constexpr Vec3 operator*(Vec3 a, const Vec3& b) { return a *= b; }
constexpr Vec3 operator*(Vec3 a, double s) { return a *= s; }
constexpr Vec3 operator*(double s, Vec3 a) { return a *= s; }
constexpr Vec3 operator/(Vec3 a, double s) { return a /= s; }
constexpr bool operator==(const Vec3& a, const Vec3& b) { return a.x == b.x && a.y == b.y && a.z == b.z; }

constexpr double dot(const Vec3& a, const Vec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
constexpr Vec3 cross(const Vec3& a, const Vec3& b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
inline double length(const Vec3& a) { return std::sqrt(dot(a, a)); }
inline Vec3 normalize(const Vec3& a) { return a / length(a); }
inline Vec3 vmin(const Vec3& a, const Vec3& b) { return {std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)}; }
inline Vec3 vmax(const Vec3& a, const Vec3& b) { return {std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)}; }
constexpr double maxComponent(const Vec3& a) { return std::max(a.x, std::max(a.y, a.z)); }
constexpr double minComponent(const Vec3& a) { return std::min(a.x, std::min(a.y, a.z)); }
inline bool isFinite(const Vec3& a) { return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z); }
constexpr bool isBlack(const Vec3& c) { return c.x == 0 && c.y == 0 && c.z == 0; }

/// Rec. 709 luminance of a linear RGB colour.
constexpr double luminance(const Color& c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; }

/// Mirror direction of w about the unit normal n: 2 (n.w) n - w.
constexpr Vec3 reflect(const Vec3& w, const Vec3& n) { return 2.0 * dot(n, w) * n - w; }

}  // namespace symphong
