// Statistical helpers for the tests: the chi-square goodness-of-fit test of a direction sampler
// against its density (after pbrt-v4 and Mitsuba's test suites), and mean / standard error.
#pragma once

#include "math/vec3.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <vector>

namespace symphong::test {

/// Regularised upper incomplete gamma function Q(a, x) (series for x < a+1, continued fraction above).
inline double gammaQ(double a, double x) {
    if (x <= 0) return 1.0;
    const double lg = std::lgamma(a);
    if (x < a + 1.0) {
        double sum = 1.0 / a, term = sum, ap = a;
        for (int n = 0; n < 10000; ++n) {
            ap += 1.0;
            term *= x / ap;
            sum += term;
            if (std::abs(term) < std::abs(sum) * 1e-15) break;
        }
        return 1.0 - sum * std::exp(-x + a * std::log(x) - lg);
    }
    double b = x + 1.0 - a, c = 1.0 / 1e-300, d = 1.0 / b, h = d;
    for (int i = 1; i < 10000; ++i) {
        const double an = -i * (i - a);
        b += 2.0;
        d = an * d + b;
        if (std::abs(d) < 1e-300) d = 1e-300;
        c = b + an / c;
        if (std::abs(c) < 1e-300) c = 1e-300;
        d = 1.0 / d;
        const double del = d * c;
        h *= del;
        if (std::abs(del - 1.0) < 1e-15) break;
    }
    return std::exp(-x + a * std::log(x) - lg) * h;
}

struct ChiSquareResult {
    double statistic = 0;
    int dof = 0;
    double pValue = 0;
    std::string describe() const {
        return "chi2 = " + std::to_string(statistic) + ", dof = " + std::to_string(dof) + ", p = " + std::to_string(pValue);
    }
};

/// Chi-square test of directions against a solid-angle density over the sphere. Cells are a
/// thetaRes x phiRes grid of (theta, phi) around +Z for theta in [0, thetaMax], plus one cell for the rest
/// of the sphere; expected counts integrate the pdf over each cell with composite Simpson rules; cells
/// with expected counts below 5 are pooled (Cochran's rule).
inline ChiSquareResult chiSquareDirections(const std::vector<Vec3>& dirs, const std::function<double(const Vec3&)>& pdf,
                                           int thetaRes, int phiRes, double thetaMax = kPi) {
    const int cells = thetaRes * phiRes;
    std::vector<double> observed(cells + 1, 0.0), expected(cells + 1, 0.0);
    const double dTheta = thetaMax / thetaRes, dPhi = kTwoPi / phiRes;
    for (const Vec3& w : dirs) {
        const double theta = std::acos(std::clamp(w.z, -1.0, 1.0));
        double phi = std::atan2(w.y, w.x);
        if (phi < 0) phi += kTwoPi;
        if (theta >= thetaMax) {
            observed[cells] += 1;
            continue;
        }
        const int i = std::min(thetaRes - 1, static_cast<int>(theta / dTheta));
        const int j = std::min(phiRes - 1, static_cast<int>(phi / dPhi));
        observed[i * phiRes + j] += 1;
    }
    // Midpoint rule on kSub x kSub sub-cells: never evaluates the pdf on a cell's edge, where densities
    // that stop at the horizon are discontinuous.
    constexpr int kSub = 16;
    double inside = 0;
    for (int i = 0; i < thetaRes; ++i)
        for (int j = 0; j < phiRes; ++j) {
            double sum = 0;
            for (int a = 0; a < kSub; ++a)
                for (int b = 0; b < kSub; ++b) {
                    const double theta = (i + (a + 0.5) / kSub) * dTheta;
                    const double phi = (j + (b + 0.5) / kSub) * dPhi;
                    const Vec3 w(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
                    sum += pdf(w) * std::sin(theta);
                }
            const double integral = sum * (dTheta / kSub) * (dPhi / kSub);
            expected[i * phiRes + j] = integral * static_cast<double>(dirs.size());
            inside += integral;
        }
    expected[cells] = std::max(0.0, 1.0 - inside) * static_cast<double>(dirs.size());

    // Pool small cells in order of expected count.
    std::vector<int> order(cells + 1);
    for (int k = 0; k <= cells; ++k) order[k] = k;
    std::sort(order.begin(), order.end(), [&](int a, int b) { return expected[a] < expected[b]; });
    ChiSquareResult r;
    double pooledExp = 0, pooledObs = 0;
    for (int k : order) {
        if (expected[k] < 5.0) {
            pooledExp += expected[k];
            pooledObs += observed[k];
        } else {
            const double diff = observed[k] - expected[k];
            r.statistic += diff * diff / expected[k];
            ++r.dof;
        }
    }
    if (pooledExp > 0) {
        const double diff = pooledObs - pooledExp;
        if (pooledExp >= 5.0) {
            r.statistic += diff * diff / pooledExp;
            ++r.dof;
        } else if (pooledObs > 2 * pooledExp + 5) {
            r.statistic = std::numeric_limits<double>::infinity();  // samples where the pdf says almost none
        }
    }
    r.dof -= 1;
    r.pValue = r.dof > 0 ? gammaQ(0.5 * r.dof, 0.5 * r.statistic) : 1.0;
    return r;
}

/// Integral of a density over the sphere by the midpoint rule on a fine (theta, phi) grid (an even
/// thetaRes puts the horizon on a cell edge, where hemispherical densities jump).
inline double integrateOverSphere(const std::function<double(const Vec3&)>& pdf, int thetaRes = 2000, int phiRes = 200) {
    const double dTheta = kPi / thetaRes, dPhi = kTwoPi / phiRes;
    double sum = 0;
    for (int i = 0; i < thetaRes; ++i) {
        const double theta = (i + 0.5) * dTheta;
        for (int j = 0; j < phiRes; ++j) {
            const double phi = (j + 0.5) * dPhi;
            const Vec3 w(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
            sum += pdf(w) * std::sin(theta);
        }
    }
    return sum * dTheta * dPhi;
}

struct MeanStd {
    double mean = 0, stdError = 0;
    std::size_t n = 0;
};

/// Mean and standard error of the mean of independent values.
inline MeanStd meanAndError(const std::vector<double>& v) {
    MeanStd r;
    r.n = v.size();
    if (v.empty()) return r;
    double s = 0;
    for (double x : v) s += x;
    r.mean = s / v.size();
    double ss = 0;
    for (double x : v) ss += (x - r.mean) * (x - r.mean);
    r.stdError = v.size() > 1 ? std::sqrt(ss / (v.size() - 1) / v.size()) : 0.0;
    return r;
}

}  // namespace symphong::test
