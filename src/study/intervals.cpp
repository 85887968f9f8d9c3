#include "study/intervals.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>

namespace symphong {

namespace {

/// The continued fraction of the regularized incomplete beta function I_x(a, b) (modified Lentz's method,
/// as in Numerical Recipes' betacf); converges for x < (a + 1) / (a + b + 2).
double betaFraction(double a, double b, double x) {
    const double tiny = 1e-300;
    double c = 1, d = 1 - (a + b) * x / (a + 1);
    if (std::abs(d) < tiny) d = tiny;
    d = 1 / d;
    double h = d;
    for (int m = 1; m <= 300; ++m) {
        const double m2 = 2.0 * m;
        double aa = m * (b - m) * x / ((a - 1 + m2) * (a + m2));
        d = 1 + aa * d, c = 1 + aa / c;
        d = std::abs(d) < tiny ? tiny : d, c = std::abs(c) < tiny ? tiny : c;
        d = 1 / d;
        h *= d * c;
        aa = -(a + m) * (a + b + m) * x / ((a + m2) * (a + 1 + m2));
        d = 1 + aa * d, c = 1 + aa / c;
        d = std::abs(d) < tiny ? tiny : d, c = std::abs(c) < tiny ? tiny : c;
        d = 1 / d;
        const double step = d * c;
        h *= step;
        if (std::abs(step - 1) < 1e-15) break;
    }
    return h;
}

/// I_x(a, b), the regularized incomplete beta function.
double incompleteBeta(double a, double b, double x) {
    if (x <= 0) return 0;
    if (x >= 1) return 1;
    const double front = std::exp(std::lgamma(a + b) - std::lgamma(a) - std::lgamma(b) + a * std::log(x) + b * std::log1p(-x));
    if (x < (a + 1) / (a + b + 2)) return front * betaFraction(a, b, x) / a;
    return 1 - front * betaFraction(b, a, 1 - x) / b;
}

/// P(T <= t) for Student's t with nu degrees of freedom: 1 - I_{nu/(nu+t^2)}(nu/2, 1/2) / 2 for t >= 0.
double studentCdf(double t, double nu) {
    const double tail = 0.5 * incompleteBeta(0.5 * nu, 0.5, nu / (nu + t * t));
    return t >= 0 ? 1 - tail : tail;
}

/// t_{0.975, dof}, remembered per thread (a study asks for the same few thousands of times).
double t975(int dof) {
    thread_local std::unordered_map<int, double> known;
    const auto it = known.find(dof);
    if (it != known.end()) return it->second;
    return known[dof] = studentQuantile(0.975, dof);
}

double mean(const std::vector<double>& v) {
    double s = 0;
    for (double x : v) s += x;
    return s / static_cast<double>(v.size());
}

}  // namespace

double studentQuantile(double p, int dof) {
    if (!(p > 0 && p < 1) || dof < 1) return std::numeric_limits<double>::quiet_NaN();
    if (p < 0.5) return -studentQuantile(1 - p, dof);
    double lo = 0, hi = 1;
    while (studentCdf(hi, dof) < p) hi *= 2;
    for (int i = 0; i < 200 && hi - lo > 1e-13 * hi; ++i) {
        const double mid = 0.5 * (lo + hi);
        (studentCdf(mid, dof) < p ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
}

std::optional<RatioInterval> efficiencyRatio(const std::vector<double>& mseA, const std::vector<double>& costA,
                                             const std::vector<double>& mseB, const std::vector<double>& costB, double commonSd) {
    const std::size_t n = mseA.size();
    if (n == 0 || costA.size() != n || mseB.size() != n || costB.size() != n) return std::nullopt;
    const double ma = mean(mseA), ca = mean(costA), mb = mean(mseB), cb = mean(costB);
    if (!(ma > 0 && ca > 0 && mb > 0 && cb > 0)) return std::nullopt;
    RatioInterval r;
    r.n = static_cast<int>(n);
    r.point = (mb * cb) / (ma * ca);
    const double common = 1.959963984540054 * commonSd * std::abs(1 / ma - 1 / mb);  // the reference's, 95%
    if (n < 2) {
        r.lo = r.point * std::exp(-common);
        r.hi = r.point * std::exp(common);
        return r;
    }
    std::vector<double> z(n);
    for (std::size_t i = 0; i < n; ++i) z[i] = mseB[i] / mb + costB[i] / cb - mseA[i] / ma - costA[i] / ca;
    const double zm = mean(z);
    double ss = 0;
    for (double x : z) ss += (x - zm) * (x - zm);
    const double se = std::sqrt(ss / static_cast<double>(n - 1) / static_cast<double>(n));
    const double h = std::hypot(t975(static_cast<int>(n) - 1) * se, common);
    r.lo = r.point * std::exp(-h);
    r.hi = r.point * std::exp(h);
    return r;
}

RatioInterval meanInterval(const std::vector<double>& values) {
    RatioInterval r;
    if (values.empty()) return r;
    r.n = static_cast<int>(values.size());
    r.point = mean(values);
    r.lo = r.hi = r.point;
    if (values.size() < 2) return r;
    double ss = 0;
    for (double x : values) ss += (x - r.point) * (x - r.point);
    const double h = t975(r.n - 1) * std::sqrt(ss / (r.n - 1) / r.n);
    const bool nonNegative = std::all_of(values.begin(), values.end(), [](double x) { return x >= 0; });
    r.lo = nonNegative ? std::max(0.0, r.point - h) : r.point - h;
    r.hi = r.point + h;
    return r;
}

Verdict verdictOf(const RatioInterval& r, double band) {
    if (r.lo >= 1 - band && r.hi <= 1 + band) return Verdict::Equal;  // first: 3% ahead for sure is still equal
    if (r.lo > 1) return Verdict::Ahead;
    if (r.hi < 1) return Verdict::Behind;
    return Verdict::Unresolved;
}

std::string verdictName(Verdict v) {
    switch (v) {
        case Verdict::Ahead: return "ahead";
        case Verdict::Behind: return "behind";
        case Verdict::Equal: return "equal";
        case Verdict::Unresolved: break;
    }
    return "not resolved";
}

bool settled(const RatioInterval& r, double target) {
    return r.n >= 2 && verdictOf(r) != Verdict::Unresolved && r.relativeHalfWidth() <= target;
}

std::string intervalText(const RatioInterval& r) {
    const auto factor = [](double x) { return x >= 10 ? fmt::format("{:.0f}x", x) : fmt::format("{:#.2g}x", x); };
    if (r.lo == r.hi) return factor(r.point);
    const auto bound = [](double x) { return x < 10 ? fmt::format("{:.2f}", x) : fmt::format("{:.3g}", x); };
    return fmt::format("{} [{}, {}]", factor(r.point), bound(r.lo), bound(r.hi));
}

}  // namespace symphong
