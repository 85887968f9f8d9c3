#include "materials/phong.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <stdexcept>

namespace symphong {

Color evalPhong(const PhongMaterial& m, const Vec3& wo, const Vec3& wi) {
    if (wo.z <= 0 || wi.z <= 0) return Color(0.0);
    Color f = m.rhoD * kInvPi;
    if (m.hasSpecular()) {
        const double ca = phongCosAlpha(wo, wi);
        if (ca > 0) f += m.rhoS * ((m.exponent + 2.0) / kTwoPi * std::pow(ca, m.exponent));
    }
    return f;
}

namespace {

// G(alpha) = integral over the azimuth beta around the lobe axis of max(0, a + b cos beta), with
// a = cos(alpha) cos(theta), b = sin(alpha) sin(theta) >= 0 (cos(theta') in the lobe's frame).
//   a >= b:        2 pi a                    (the whole ring is above the horizon)
//   |a| < b:       2 (a acos(-a/b) + sqrt(b^2 - a^2))
//   a <= -b:       0
double azimuthIntegral(double cosAlpha, double cosTheta, double sinTheta) {
    const double sinAlpha = std::sqrt(std::max(0.0, 1.0 - cosAlpha * cosAlpha));
    const double a = cosAlpha * cosTheta, b = sinAlpha * sinTheta;
    if (a >= b) return kTwoPi * a;
    if (a <= -b) return 0.0;
    return 2.0 * (a * std::acos(-a / b) + std::sqrt(std::max(0.0, b * b - a * a)));
}

double simpson(const std::function<double(double)>& f, double a, double b, double fa, double fm, double fb, double whole, double tol,
               int depth) {
    const double m = 0.5 * (a + b), lm = 0.5 * (a + m), rm = 0.5 * (m + b);
    const double flm = f(lm), frm = f(rm);
    const double left = (m - a) / 6.0 * (fa + 4.0 * flm + fm);
    const double right = (b - m) / 6.0 * (fm + 4.0 * frm + fb);
    const double delta = left + right - whole;
    if (depth <= 0 || std::abs(delta) <= 15.0 * tol) return left + right + delta / 15.0;
    return simpson(f, a, m, fa, flm, fm, left, 0.5 * tol, depth - 1) + simpson(f, m, b, fm, frm, fb, right, 0.5 * tol, depth - 1);
}

// Adaptive Simpson over [a,b], started from `panels` equal panels so that narrow features are seen.
double integrate(const std::function<double(double)>& f, double a, double b, double tol, int panels = 64) {
    double sum = 0;
    const double h = (b - a) / panels;
    for (int i = 0; i < panels; ++i) {
        const double x0 = a + i * h, x1 = x0 + h, xm = 0.5 * (x0 + x1);
        const double f0 = f(x0), fm = f(xm), f1 = f(x1);
        sum += simpson(f, x0, x1, f0, fm, f1, h / 6.0 * (f0 + 4.0 * fm + f1), tol / panels, 40);
    }
    return sum;
}

}  // namespace

// I(n, theta) = int_0^{pi/2} cos^n(alpha) sin(alpha) G(alpha) d alpha. With t = cos(alpha) and
// s = t^(n+1) (so ds = (n+1) t^n dt) the lobe's weight becomes uniform in s:
//   I = 1/(n+1) int_0^1 G(acos(s^(1/(n+1)))) ds,
// which stays well resolved for n up to 1e4 and beyond. G has a kink where the ring first touches the
// horizon, alpha = pi/2 - theta, i.e. s = sin(theta)^(n+1); we split there.
double phongLobeCosineIntegral(double n, double theta) {
    const double cosTheta = std::cos(theta), sinTheta = std::sin(theta);
    const double inv = 1.0 / (n + 1.0);
    const auto g = [&](double s) { return azimuthIntegral(std::pow(s, inv), cosTheta, sinTheta); };
    const double scale = kTwoPi / (n + 2.0);  // the value at theta = 0, sets the absolute tolerance
    const double tol = 1e-11 * scale * (n + 1.0);
    const double kink = std::pow(sinTheta, n + 1.0);
    double total = 0;
    if (kink > 0 && kink < 1) {
        total = integrate(g, 0.0, kink, tol) + integrate(g, kink, 1.0, tol);
    } else {
        total = integrate(g, 0.0, 1.0, tol);
    }
    return total * inv;
}

Color phongDirectionalAlbedo(const PhongMaterial& m, const Vec3& wo) {
    if (wo.z <= 0) return Color(0.0);
    Color a = m.rhoD;
    if (m.hasSpecular()) {
        const double theta = std::acos(std::min(1.0, wo.z));
        a += m.rhoS * ((m.exponent + 2.0) / kTwoPi * phongLobeCosineIntegral(m.exponent, theta));
    }
    return a;
}

bool validateAndClampPhong(PhongMaterial& m) {
    const auto check = [&](const Color& c, const char* what) {
        for (int i = 0; i < 3; ++i)
            if (!std::isfinite(c[i]) || c[i] < 0)
                throw std::invalid_argument(
                    fmt::format("material '{}': {} component {} is {} (must be finite and >= 0)", m.name, what, i, c[i]));
    };
    check(m.rhoD, "diffuse albedo Kd");
    check(m.rhoS, "specular albedo Ks");
    check(m.emission, "emission Ke");
    if (!std::isfinite(m.exponent) || m.exponent < 0)
        throw std::invalid_argument(fmt::format("material '{}': Phong exponent Ns is {} (must be finite and >= 0)", m.name, m.exponent));
    return clampEnergy(m.rhoD, m.rhoS);
}

bool clampEnergy(Color& rhoD, Color& rhoS) {
    bool clamped = false;
    for (int i = 0; i < 3; ++i) {
        const double sum = rhoD[i] + rhoS[i];
        if (sum > 1.0) {
            rhoD[i] /= sum;
            rhoS[i] /= sum;
            clamped = true;
        }
    }
    return clamped;
}

void metallicRoughnessToPhong(const Color& baseIn, double metallic, double roughness, const Color& f0In, Color& rhoD, Color& rhoS,
                              double& exponent) {
    // Copies: a caller may pass its rho_d as the base colour (the FBX and MTL readers do), which the first
    // assignment would overwrite before rho_s reads it.
    const Color base = baseIn, f0 = f0In;
    rhoD = base * ((1.0 - metallic) * (1.0 - maxComponent(f0)));
    rhoS = f0 * (1.0 - metallic) + base * metallic;
    const double alpha = std::max(1e-3, roughness * roughness);
    exponent = std::clamp(2.0 / (alpha * alpha) - 2.0, 0.0, 1e4);
}

}  // namespace symphong
