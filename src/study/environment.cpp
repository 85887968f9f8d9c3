#include "study/environment.h"

#include "math/frame.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <stdexcept>

namespace symphong {

double Environment::radiance(const Vec3& w) const {
    for (const SphericalCap& c : caps)
        if (!c.contains(w)) return 0.0;
    const double t = dot(w, g);
    return c0 + c1 * t + c2 * t * t;
}

const std::vector<std::string>& environmentNames() {
    static const std::vector<std::string> names = {"constant", "gradient", "disk", "band", "halfspace"};
    return names;
}

Environment makeEnvironment(const std::string& name, const EnvironmentParams& p) {
    const double deg = kPi / 180.0;
    Environment e;
    e.name = name;
    if (name == "constant") {
        e.description = "L = 1 everywhere";
    } else if (name == "gradient") {
        e.g = normalize(Vec3(0.4, -0.3, 0.85));
        e.c0 = 0.5, e.c1 = 0.4, e.c2 = 0.3;
        e.description = "sky gradient L = 0.5 + 0.4 t + 0.3 t^2, t = w . normalize(0.4, -0.3, 0.85)";
    } else if (name == "disk") {
        if (!(p.diskRadius > 0 && p.diskRadius < 90))
            throw std::invalid_argument(fmt::format("disk radius {} must lie in (0, 90) degrees", p.diskRadius));
        const double t = p.diskTheta * deg, ph = p.diskPhi * deg;
        e.caps.push_back({Vec3(std::sin(t) * std::cos(ph), std::sin(t) * std::sin(ph), std::cos(t)), std::cos(p.diskRadius * deg)});
        e.description = fmt::format("disk light L = 1 of radius {} deg at theta {} deg, phi {} deg", p.diskRadius, p.diskTheta, p.diskPhi);
    } else if (name == "band") {
        if (!(p.bandDegrees > 0 && p.bandDegrees <= 90))
            throw std::invalid_argument(fmt::format("band height {} must lie in (0, 90] degrees", p.bandDegrees));
        e.caps.push_back({Vec3(0, 0, 1), 0.0});
        e.caps.push_back({Vec3(0, 0, -1), -std::sin(p.bandDegrees * deg)});
        e.description = fmt::format("L = 1 in the band 0 <= elevation <= {} deg above the horizon", p.bandDegrees);
    } else if (name == "halfspace") {
        e.caps.push_back({normalize(Vec3(1.0, 0.3, 0.2)), 0.0});
        e.description = "L = 1 on the half-space w . normalize(1, 0.3, 0.2) >= 0";
    } else {
        std::string list;
        for (const auto& n : environmentNames()) list += (list.empty() ? "" : ", ") + n;
        throw std::invalid_argument(fmt::format("unknown environment '{}' (valid: {})", name, list));
    }
    return e;
}

namespace {

/// 32-point Gauss-Legendre nodes and weights on [-1, 1] (Newton on P_32, computed once).
struct GaussLegendre {
    static constexpr int kN = 32;
    std::array<double, kN> x{}, w{};
    GaussLegendre() {
        for (int i = 0; i < kN; ++i) {
            double z = std::cos(kPi * (i + 0.75) / (kN + 0.5)), dp = 0;
            for (int it = 0; it < 100; ++it) {
                double p0 = 1, p1 = z;
                for (int k = 2; k <= kN; ++k) {
                    const double p2 = ((2 * k - 1) * z * p1 - (k - 1) * p0) / k;
                    p0 = p1;
                    p1 = p2;
                }
                dp = kN * (z * p1 - p0) / (z * z - 1);
                const double dz = p1 / dp;
                z -= dz;
                if (std::abs(dz) < 1e-16) break;
            }
            x[i] = z;
            w[i] = 2.0 / ((1 - z * z) * dp * dp);
        }
    }
};
const GaussLegendre& gl() {
    static const GaussLegendre g;
    return g;
}

using Interval = std::pair<double, double>;

/// Intersection of two sorted lists of disjoint intervals.
std::vector<Interval> intersect(const std::vector<Interval>& a, const std::vector<Interval>& b) {
    std::vector<Interval> out;
    for (const auto& x : a)
        for (const auto& y : b) {
            const double lo = std::max(x.first, y.first), hi = std::min(x.second, y.second);
            if (hi > lo) out.emplace_back(lo, hi);
        }
    std::sort(out.begin(), out.end());
    return out;
}

/// Integral over beta in [0, 2 pi) of h(w(alpha, beta)) where w = cos(alpha) A + sin(alpha)(cos(beta) T +
/// sin(beta) B), restricted to the caps.
double ringIntegral(const Frame& f, double alpha, const std::vector<SphericalCap>& caps, const std::function<double(const Vec3&)>& h) {
    const double ca = std::cos(alpha), sa = std::sin(alpha);
    std::vector<Interval> allowed = {{0.0, kTwoPi}};
    for (const SphericalCap& c : caps) {
        const double p = dot(c.axis, f.n), q = dot(c.axis, f.s), r = dot(c.axis, f.t);
        const double P = ca * p, R = sa * std::sqrt(q * q + r * r);
        std::vector<Interval> set;
        if (R < 1e-14) {
            if (P >= c.cosRadius) set = {{0.0, kTwoPi}};
        } else {
            const double t = (c.cosRadius - P) / R;
            if (t <= -1) {
                set = {{0.0, kTwoPi}};
            } else if (t < 1) {
                const double half = std::acos(t);
                double lo = std::atan2(r, q) - half;
                lo -= kTwoPi * std::floor(lo / kTwoPi);
                const double hi = lo + 2 * half;
                if (hi <= kTwoPi)
                    set = {{lo, hi}};
                else
                    set = {{0.0, hi - kTwoPi}, {lo, kTwoPi}};
            }
        }
        allowed = intersect(allowed, set);
        if (allowed.empty()) return 0.0;
    }
    double sum = 0;
    const GaussLegendre& g = gl();
    for (const auto& [lo, hi] : allowed) {
        const double mid = 0.5 * (lo + hi), half = 0.5 * (hi - lo);
        double s = 0;
        for (int i = 0; i < GaussLegendre::kN; ++i) {
            const double b = mid + half * g.x[i];
            s += g.w[i] * h(f.n * ca + (f.s * std::cos(b) + f.t * std::sin(b)) * sa);
        }
        sum += s * half;
    }
    return sum;
}

double simpson(const std::function<double(double)>& fn, double a, double b, double fa, double fm, double fb, double whole, double tol,
               int depth) {
    const double m = 0.5 * (a + b);
    const double flm = fn(0.5 * (a + m)), frm = fn(0.5 * (m + b));
    const double left = (m - a) / 6 * (fa + 4 * flm + fm), right = (b - m) / 6 * (fm + 4 * frm + fb);
    const double delta = left + right - whole;
    if (depth <= 0 || std::abs(delta) <= 15 * tol) return left + right + delta / 15;
    return simpson(fn, a, m, fa, flm, fm, left, tol / 2, depth - 1) + simpson(fn, m, b, fm, frm, fb, right, tol / 2, depth - 1);
}

/// Adaptive Simpson over [a, b] split at `breaks`, each piece started from 16 panels.
double integrate(const std::function<double(double)>& fn, double a, double b, std::vector<double> breaks, double tol) {
    breaks.push_back(a);
    breaks.push_back(b);
    std::sort(breaks.begin(), breaks.end());
    double sum = 0;
    for (std::size_t i = 0; i + 1 < breaks.size(); ++i) {
        const double lo = std::max(a, breaks[i]), hi = std::min(b, breaks[i + 1]);
        if (hi <= lo) continue;
        constexpr int kPanels = 16;
        const double h = (hi - lo) / kPanels;
        for (int k = 0; k < kPanels; ++k) {
            const double x0 = lo + k * h, x1 = x0 + h;
            const double f0 = fn(x0), fm = fn(0.5 * (x0 + x1)), f1 = fn(x1);
            sum += simpson(fn, x0, x1, f0, fm, f1, h / 6 * (f0 + 4 * fm + f1), tol / kPanels, 30);
        }
    }
    return sum;
}

/// Polar angles (from frame axis A) where a cap's boundary circle is tangent to a ring: |gamma -/+ rho|.
std::vector<double> tangencies(const Vec3& axis, const std::vector<SphericalCap>& caps) {
    std::vector<double> out;
    for (const SphericalCap& c : caps) {
        const double gamma = std::acos(std::clamp(dot(axis, c.axis), -1.0, 1.0));
        const double rho = std::acos(std::clamp(c.cosRadius, -1.0, 1.0));
        for (double v : {std::abs(gamma - rho), gamma + rho, kTwoPi - gamma - rho}) out.push_back(v);
    }
    return out;
}

}  // namespace

double exactReflected(const Environment& env, double rhoD, double rhoS, double n, const Vec3& wo) {
    double total = 0;
    if (rhoD > 0) {
        // (rho_d / pi) int L cos(theta) dw over the hemisphere, polar angle from the normal.
        const Frame f = Frame::fromNormal(Vec3(0, 0, 1));
        const auto L = [&](const Vec3& w) { return env.radiance(w) * w.z; };
        const auto ring = [&](double a) { return ringIntegral(f, a, env.caps, L) * std::sin(a); };
        total += rhoD * kInvPi * integrate(ring, 0.0, kPi / 2, tangencies(f.n, env.caps), 1e-13);
    }
    if (rhoS > 0) {
        // rho_s (n+2)/(2 pi) int cos^n(alpha) L max(0, cos theta) dw, polar angle alpha from the mirror
        // direction r; with s = cos^(n+1)(alpha): 1/(n+1) int_0^1 ring(alpha(s)) ds.
        const Vec3 r(-wo.x, -wo.y, wo.z);
        const Frame f = Frame::fromNormal(r);
        std::vector<SphericalCap> caps = env.caps;
        caps.push_back({Vec3(0, 0, 1), 0.0});
        const auto L = [&](const Vec3& w) { return env.radiance(w) * w.z; };
        const auto ringOfS = [&](double s) { return ringIntegral(f, std::acos(std::pow(s, 1.0 / (n + 1.0))), caps, L); };
        std::vector<double> breaks;
        for (double a : tangencies(f.n, caps))
            if (a > 0 && a < kPi / 2) breaks.push_back(std::pow(std::cos(a), n + 1.0));
        total += rhoS * (n + 2.0) / kTwoPi / (n + 1.0) * integrate(ringOfS, 0.0, 1.0, breaks, 1e-13);
    }
    return total;
}

}  // namespace symphong
