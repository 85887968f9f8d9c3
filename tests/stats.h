// Statistical helpers for the tests: Pearson's chi-square goodness-of-fit test of a direction sampler
// against the solid-angle density it claims (after pbrt-v4's BSDF chi-square test, src/pbrt/bsdfs_test.cpp,
// and Mitsuba 3's mitsuba.chi2.ChiSquareTest), the same test on plain counts, the Sidak correction,
// the regularised incomplete gamma function, and the mean / standard error of independent values.
// docs/testing.md explains the method and the suite's statistical rules.
//
// API
//   ChiSquareResult r = chiSquareSphere(dirs, pdf, opts);      // one run
//   EXPECT_TRUE(r.passed) << r.describe();
//     dirs   independent directions (unit vectors, any frame) drawn from the sampler under test;
//     pdf    the density the sampler claims, per unit solid angle, over the WHOLE sphere (0 where it never
//            samples): every cell's expected count is the integral of pdf over that cell;
//     opts   ChiSquareOptions: thetaRes (odd) x phiRes cells, the grid's pole `axis`, a `concentration`
//            that gives narrow lobes rows of their own, and `alpha`, the significance of this run: pass
//            sidakAlpha(runs) when a test makes `runs` runs, so the whole test rejects a correct sampler
//            with probability 0.01.
//   r.passed is false when (checked in this order, all reported by r.describe()):
//     - some directions are not finite unit vectors;
//     - the pdf is negative or not finite somewhere the integration looked;
//     - the pdf does not integrate to 1 over the sphere within opts.normTolerance (r.pdfIntegral), so a
//       pdf off by a constant factor fails even when the statistic cannot see it;
//     - any direction falls in a cell where the pdf integrates to 0 (strict, as Mitsuba: see below);
//     - fewer than opts.minDof degrees of freedom (too coarse a grid or too few samples to test anything);
//     - the p-value of the statistic is below alpha.
//   SphereChiSquare grid(pdf, opts); grid.test(dirs) ...       // integrates once, tests many sample sets
//   chiSquareCounts(observed, expected, alpha)                  // the same pooling / zero-cell rules on
//                                                               // any finite set of cells
//   sidakAlpha(runs, 0.01)                                      // 1 - (1 - 0.01)^(1/runs)
//   integrateSphereAdaptive(f, opts)                             // the grid's quadrature of any f >= 0
//   gammaQ(a, x), meanAndError(values), integrateOverSphere(pdf) (midpoint rule; kept for old callers)
//
// Method (SphereChiSquare)
//   Cells. The sphere, in a frame whose pole is opts.axis, is cut into thetaRes rows by the cosine z of
//   the angle from the pole and phiRes columns of equal azimuth. With concentration c = 0 the rows are
//   equal steps of z, so all cells have the same solid angle (Mitsuba's spherical domain). With c > 0
//   the rows are equal steps of s = 1 - ((1+z)/2)^(c+1), so a cos^n lobe about the axis with n ~ c is
//   spread over all rows instead of sitting in the first one (row i holds about (2(R-i)-1)/R^2 of it).
//   There is no partial grid and no "rest of the sphere" cell: every cell is integrated, so an error
//   in the pdf anywhere shows up in its own cells and in the normalisation.
//   Odd thetaRes (required). With the axis on the normal and c = 0, the horizon z = 0 then lies in the
//   middle of the middle row instead of on a row edge. That is the right choice for hemisphere
//   densities: a direction that rounds to z = 0 or to -1e-17 lands in a row whose expectation is
//   positive, so the strict zero-cell rule cannot fire on round-off, while every row below it has
//   expectation exactly 0 and any sample there (more than half a row below the horizon) fails the
//   test outright; a leak within half a row is an excess in the straddling row, which the statistic
//   sees. The price is a density discontinuous inside those cells, which the adaptive integration
//   handles (its first bisection of that row falls on z = 0). An even resolution would put z = 0 on an
//   edge, where one ulp decides between "fine" and "rejected".
//   Expected counts. N times the integral of pdf over each cell, by nested adaptive Simpson quadrature
//   in (z, phi) (solid angle is dz dphi: no Jacobian, no singular pole), Lyness's stopping rule with
//   Richardson extrapolation as in pbrt-v4, inner integral over phi, outer over z. The pdf may jump
//   (horizon, edges of pieces): the tolerance per sub-interval is absolute (opts.tolerance), not
//   halved per level, so the recursion converges at a jump (after ~log2(jump * width / tol) levels)
//   instead of running to its depth limit. Every cell is split 2 x 2 before the stopping rule applies;
//   cells at the edge of the support (the pdf seen zero and positive in them, or zero in them and
//   positive in a neighbour) are integrated again split 16 x 16, so that thin slivers of support at
//   corners are not skipped. Measured accuracy: the whole-sphere integral within 1e-8 for every density
//   of the suite (hemispheres, lobes to n = 10^4, the Uniform Separation's pieces), closed-form cell
//   integrals within 1e-10. A cell whose integral still comes out 0 but holds a sample where the pdf
//   is positive is integrated again split 64 x 64 before the zero-cell rule is applied.
//   Zero cells. Strict (Mitsuba): one sample in a cell where the pdf integrates to 0 rejects. pbrt
//   tolerates 1e-5 N such samples because it works in single precision; here sampling, binning and
//   integration are in double precision, and round-off can only put a correct sample into a zero cell
//   where a support edge is also a cell edge: the horizon is not (it sits inside a row, above), and of
//   the Uniform Separation's piece edges (azimuths k pi/4) only 0 and pi are column edges (phiRes =
//   2 x odd is never a multiple of 4), which the maps reach from inside (y >= 0 exactly). So a sample
//   in a zero cell is a bug, not round-off.
//   Pooling. Cells with positive expectation are sorted by expected count; starting from the smallest,
//   cells are merged into a pool until it reaches minExpected (5, Cochran's rule), then the pool is
//   counted as one cell and a new pool starts (Mitsuba); cells already at 5 or more stand alone. A
//   last pool that never reaches 5 is merged into the previous counted pool: it is always counted.
//   The grouping depends on the expected counts only, so the statistic is chi-square distributed
//   with dof = counted cells - 1 under the null hypothesis; p = Q(dof/2, chi2/2).
#pragma once

#include "math/frame.h"
#include "math/vec3.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace symphong::test {

/// Regularised upper incomplete gamma function Q(a, x) (series for x < a+1, continued fraction above).
inline double gammaQ(double a, double x) {
    if (x <= 0) return 1.0;
    if (std::isinf(x)) return 0.0;
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

/// P(X >= statistic) for X chi-square distributed with dof degrees of freedom (0 for a non-finite statistic).
inline double chiSquarePValue(double statistic, int dof) {
    if (!(statistic == statistic) || std::isinf(statistic)) return 0.0;
    return dof > 0 ? gammaQ(0.5 * dof, 0.5 * statistic) : 1.0;
}

/// Per-run significance for `runs` independent runs that together reject a correct sampler with
/// probability familyAlpha (Sidak): 1 - (1 - familyAlpha)^(1/runs).
inline double sidakAlpha(int runs, double familyAlpha = 0.01) { return -std::expm1(std::log1p(-familyAlpha) / std::max(1, runs)); }

struct ChiSquareOptions {
    int thetaRes = 21;            ///< rows (must be odd: see the header comment)
    int phiRes = 0;               ///< columns of equal azimuth; 0 means 2 * thetaRes
    Vec3 axis{0, 0, 1};           ///< the grid's pole (the normal, or a lobe's axis)
    double concentration = 0;     ///< rows equal in s = 1 - ((1+z)/2)^(c+1); 0: equal solid angles
    double alpha = 0.01;          ///< significance of this run (sidakAlpha(runs) for several runs)
    double minExpected = 5;       ///< pools reach this expected count (Cochran)
    int minDof = 10;              ///< fewer degrees of freedom fail: the run would not test anything
    double normTolerance = 1e-4;  ///< |integral of pdf over the sphere - 1| allowed
    double tolerance = 1e-11;     ///< absolute quadrature tolerance per sub-interval (probability units)
};

struct ChiSquareResult {
    bool passed = false;
    double statistic = 0;
    int dof = 0;
    double pValue = 0;
    double alpha = 0;
    std::size_t samples = 0;
    double pdfIntegral = 1;  ///< integral of the pdf over all cells (sphere tests), else 1
    double normTolerance = 0;
    std::size_t badSamples = 0;       ///< not finite unit vectors
    std::size_t zeroCellSamples = 0;  ///< samples in cells whose expected count is 0
    int cells = 0, zeroCells = 0;     ///< cells, and cells with expectation 0 (their samples: above)
    int pooledCells = 0, pools = 0;   ///< cells below minExpected merged, and the pools they made
    std::string failure;              ///< why the run failed; empty when passed
    std::string worst;                ///< the counted cells that contribute most to the statistic

    std::string describe() const {
        char buf[512];
        std::snprintf(buf, sizeof buf,
                      "%s: chi2 = %.2f, dof = %d, p = %.3g (alpha = %.3g); N = %zu, %d cells (%d with expectation 0 "
                      "holding %zu samples; %d pooled into %d)",
                      passed ? "accepted" : "REJECTED", statistic, dof, pValue, alpha, samples, cells, zeroCells, zeroCellSamples,
                      pooledCells, pools);
        std::string s = buf;
        if (normTolerance > 0) {
            std::snprintf(buf, sizeof buf, "; pdf integrates to %.8f (tolerance %.1e)", pdfIntegral, normTolerance);
            s += buf;
        }
        if (!failure.empty()) s += "\n  failure: " + failure;
        if (!worst.empty()) s += "\n  largest contributions: " + worst;
        return s;
    }
};

/// Pearson's test of observed counts against expected counts (same total) with the pooling and
/// zero-cell rules of the header comment. cellName(i) names cell i in messages (optional).
inline ChiSquareResult chiSquareCounts(const std::vector<double>& observed, const std::vector<double>& expected, double alpha = 0.01,
                                       double minExpected = 5.0, const std::function<std::string(std::size_t)>& cellName = {}) {
    ChiSquareResult r;
    r.alpha = alpha;
    r.cells = static_cast<int>(expected.size());
    for (double o : observed) r.samples += static_cast<std::size_t>(o);
    const auto name = [&](std::size_t i) { return cellName ? cellName(i) : "cell " + std::to_string(i); };
    if (observed.size() != expected.size()) {
        r.failure = "observed and expected counts differ in size";
        return r;
    }

    std::vector<std::size_t> order;
    std::string zeroMessage;
    for (std::size_t i = 0; i < expected.size(); ++i) {
        if (!(expected[i] >= 0) || !std::isfinite(expected[i])) {
            r.failure = "expected count " + std::to_string(expected[i]) + " in " + name(i);
            return r;
        }
        if (expected[i] > 0) {
            order.push_back(i);
        } else {
            ++r.zeroCells;
            if (observed[i] > 0) {
                r.zeroCellSamples += static_cast<std::size_t>(observed[i]);
                if (zeroMessage.size() < 400)
                    zeroMessage +=
                        (zeroMessage.empty() ? "" : "; ") + name(i) + " holds " + std::to_string(static_cast<long long>(observed[i]));
            }
        }
    }
    // Smallest expectation first; ties by index, so the grouping never depends on the observations.
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return expected[a] < expected[b]; });

    struct Term {
        double obs = 0, exp = 0;
        int cells = 0;
        std::size_t first = 0;
    };
    std::vector<Term> terms;
    Term pool;
    for (std::size_t i : order) {
        if (pool.cells > 0 || expected[i] < minExpected) {
            if (pool.cells == 0) pool.first = i;
            pool.obs += observed[i];
            pool.exp += expected[i];
            ++pool.cells;
            ++r.pooledCells;
            if (pool.exp >= minExpected) {
                terms.push_back(pool);
                ++r.pools;
                pool = Term{};
            }
        } else {
            terms.push_back({observed[i], expected[i], 1, i});
        }
    }
    if (pool.cells > 0) {  // a last pool short of minExpected: merged into the previous pool, never dropped
        if (!terms.empty()) {
            terms.back().obs += pool.obs;
            terms.back().exp += pool.exp;
            terms.back().cells += pool.cells;
            if (terms.back().cells == pool.cells + 1) ++r.pools;  // it was a single cell, now a pool
        } else {
            terms.push_back(pool);
            ++r.pools;
        }
    }

    std::vector<std::pair<double, std::size_t>> contributions;
    for (std::size_t k = 0; k < terms.size(); ++k) {
        const double d = terms[k].obs - terms[k].exp;
        const double c = d * d / terms[k].exp;
        r.statistic += c;
        contributions.emplace_back(c, k);
    }
    r.dof = static_cast<int>(terms.size()) - 1;
    r.pValue = chiSquarePValue(r.statistic, r.dof);
    std::sort(contributions.begin(), contributions.end(), std::greater<>());
    for (std::size_t k = 0; k < std::min<std::size_t>(3, contributions.size()); ++k) {
        const Term& t = terms[contributions[k].second];
        char buf[200];
        std::snprintf(buf, sizeof buf, "%s%s: observed %.0f, expected %.1f (+%.1f)", k ? "; " : "",
                      t.cells > 1 ? ("pool of " + std::to_string(t.cells) + " cells from " + name(t.first)).c_str() : name(t.first).c_str(),
                      t.obs, t.exp, contributions[k].first);
        r.worst += buf;
    }

    if (r.zeroCellSamples > 0)
        r.failure = std::to_string(r.zeroCellSamples) + " samples in cells where the density integrates to 0 (" + zeroMessage + ")";
    else if (r.dof < 1)
        r.failure = "no degrees of freedom";
    else if (!(r.pValue >= alpha))
        r.failure = "p-value below the significance level";
    r.passed = r.failure.empty();
    return r;
}

namespace detail {

/// One level of adaptive Simpson on [a, c] (midpoint m, values fa, fm, fc, Simpson estimate `whole`):
/// Lyness's criterion |S2 - S1| <= 15 eps with Richardson extrapolation, as pbrt-v4's AdaptiveSimpson,
/// but with an absolute eps that is not halved per level, so that a jump in f converges.
template <class F>
double simpsonLevel(const F& f, double a, double m, double c, double fa, double fm, double fc, double whole, double eps, int depth,
                    int minDepth) {
    const double d = 0.5 * (a + m), e = 0.5 * (m + c);
    const double fd = f(d), fe = f(e);
    const double h = c - a;
    const double left = h / 12.0 * (fa + 4.0 * fd + fm), right = h / 12.0 * (fm + 4.0 * fe + fc);
    const double both = left + right;
    if (minDepth <= 0 && std::abs(both - whole) <= 15.0 * eps) return both + (both - whole) / 15.0;
    if (depth <= 0 || !(d > a && d < m && e > m && e < c)) return both;  // no extrapolation without convergence
    return simpsonLevel(f, a, d, m, fa, fd, fm, left, eps, depth - 1, minDepth - 1) +
           simpsonLevel(f, m, e, c, fm, fe, fc, right, eps, depth - 1, minDepth - 1);
}

template <class F>
double adaptiveSimpson(const F& f, double a, double c, double eps, int minDepth, int maxDepth = 50) {
    const double m = 0.5 * (a + c);
    const double fa = f(a), fm = f(m), fc = f(c);
    return simpsonLevel(f, a, m, c, fa, fm, fc, (c - a) / 6.0 * (fa + 4.0 * fm + fc), eps, maxDepth, minDepth);
}

}  // namespace detail

/// The chi-square test of directions against a density on a grid over the whole sphere (header
/// comment). Construction integrates the density over every cell; test() bins a sample set and tests it.
class SphereChiSquare {
public:
    SphereChiSquare(std::function<double(const Vec3&)> pdf, const ChiSquareOptions& opts = {}) : pdf_(std::move(pdf)), opts_(opts) {
        if (opts_.thetaRes < 1 || opts_.thetaRes % 2 == 0)
            throw std::invalid_argument("chi-square grid: thetaRes must be odd (the horizon inside a row), got " +
                                        std::to_string(opts_.thetaRes));
        if (opts_.phiRes <= 0) opts_.phiRes = 2 * opts_.thetaRes;
        if (!(length(opts_.axis) > 0)) throw std::invalid_argument("chi-square grid: zero axis");
        frame_ = Frame::fromNormal(normalize(opts_.axis));
        rows_ = opts_.thetaRes;
        cols_ = opts_.phiRes;
        dPhi_ = kTwoPi / cols_;
        // Row edges, descending from z = 1 to z = -1: s = i/R, z = 2 ((1 - s)^(1/(c+1))) - 1.
        edges_.resize(rows_ + 1);
        for (int i = 0; i <= rows_; ++i) {
            const double s = static_cast<double>(i) / rows_;
            edges_[i] = opts_.concentration == 0 ? 1.0 - 2.0 * s : 1.0 + 2.0 * std::expm1(std::log1p(-s) / (opts_.concentration + 1.0));
        }
        edges_[0] = 1.0;
        edges_[rows_] = -1.0;
        // Every cell split 2 x 2 first; then the cells at the edge of the support (the pdf seen both
        // zero and positive in them, or only zero in them next to a cell where it is positive) again,
        // split 16 x 16, so that a thin sliver of support at a corner is not missed.
        const std::size_t cells = static_cast<std::size_t>(rows_) * cols_;
        prob_.resize(cells);
        std::vector<unsigned char> seen(cells);
        for (int i = 0; i < rows_; ++i)
            for (int j = 0; j < cols_; ++j) prob_[i * cols_ + j] = integrateCell(i, j, 1, &seen[i * cols_ + j]);
        const auto positiveAt = [&](int i, int j) { return i >= 0 && i < rows_ && (seen[i * cols_ + (j + cols_) % cols_] & kSawPositive); };
        for (int i = 0; i < rows_; ++i)
            for (int j = 0; j < cols_; ++j) {
                const unsigned char f = seen[i * cols_ + j];
                bool edge = (f & kSawPositive) && (f & kSawZero);
                for (int di = -1; di <= 1 && !edge && !(f & kSawPositive); ++di)
                    for (int dj = -1; dj <= 1; ++dj) edge = edge || positiveAt(i + di, j + dj);
                if (edge) prob_[i * cols_ + j] = integrateCell(i, j, 4);
            }
        total_ = 0;
        for (double p : prob_) total_ += p;
    }

    int rows() const { return rows_; }
    int cols() const { return cols_; }
    /// Integral of the pdf over cell (row, col).
    double cellProbability(int row, int col) const { return prob_[row * cols_ + col]; }
    /// Integral of the pdf over the sphere (the sum over the cells).
    double pdfIntegral() const { return total_; }
    /// The pdf was negative or not finite at some point the quadrature evaluated (with one such point).
    bool pdfInvalid() const { return !invalid_.empty(); }

    /// Cell index (row * cols + col) of a direction; -1 when it is not a finite unit vector.
    int cellOf(const Vec3& w) const {
        if (!isFinite(w) || std::abs(dot(w, w) - 1.0) > 1e-6) return -1;
        const Vec3 l = frame_.toLocal(w);
        const double z = std::clamp(l.z, -1.0, 1.0);
        // First edge below z (edges descend): row k-1 spans [edges[k], edges[k-1]].
        const auto k = std::upper_bound(edges_.begin(), edges_.end(), z, std::greater<double>()) - edges_.begin();
        const int row = std::clamp(static_cast<int>(k) - 1, 0, rows_ - 1);
        double phi = std::atan2(l.y, l.x);
        if (phi < 0) phi += kTwoPi;
        const int col = std::clamp(static_cast<int>(phi / dPhi_), 0, cols_ - 1);
        return row * cols_ + col;
    }

    std::string cellName(std::size_t cell) const {
        const int i = static_cast<int>(cell) / cols_, j = static_cast<int>(cell) % cols_;
        char buf[160];
        std::snprintf(buf, sizeof buf, "cell (row %d, col %d: cos %.4f..%.4f, phi %.1f..%.1f deg about the axis)", i, j, edges_[i + 1],
                      edges_[i], j * dPhi_ * 180 / kPi, (j + 1) * dPhi_ * 180 / kPi);
        return buf;
    }

    ChiSquareResult test(const std::vector<Vec3>& dirs) const {
        const std::size_t n = dirs.size();
        std::vector<double> observed(prob_.size(), 0.0);
        std::size_t bad = 0;
        std::string badExample;
        for (const Vec3& w : dirs) {
            const int c = cellOf(w);
            if (c < 0) {
                if (bad++ == 0) badExample = "(" + std::to_string(w.x) + ", " + std::to_string(w.y) + ", " + std::to_string(w.z) + ")";
                continue;
            }
            observed[c] += 1;
        }
        // A zero cell that holds a sample where the pdf is positive: the quadrature missed a sliver of
        // support; integrate that cell again, split 64 x 64.
        std::vector<double> prob = prob_;
        double total = total_;
        std::vector<char> recheck(prob.size(), 0);
        bool any = false;
        for (std::size_t c = 0; c < prob.size(); ++c)
            if (prob[c] == 0 && observed[c] > 0) recheck[c] = any = true;
        std::string zeroExample;
        if (any) {
            std::vector<char> positive(prob.size(), 0);
            for (const Vec3& w : dirs) {
                const int c = cellOf(w);
                if (c < 0 || !recheck[c]) continue;
                const double p = pdf_(w);
                if (p > 0)
                    positive[c] = 1;
                else if (zeroExample.empty())
                    zeroExample = "e.g. (" + std::to_string(w.x) + ", " + std::to_string(w.y) + ", " + std::to_string(w.z) +
                                  ") where pdf = " + std::to_string(p) + " in " + cellName(c);
            }
            for (std::size_t c = 0; c < prob.size(); ++c)
                if (positive[c]) {
                    prob[c] = integrateCell(static_cast<int>(c) / cols_, static_cast<int>(c) % cols_, 6);
                    total += prob[c];
                }
        }
        std::vector<double> expected(prob.size());
        for (std::size_t c = 0; c < prob.size(); ++c) expected[c] = prob[c] * static_cast<double>(n);

        ChiSquareResult r =
            chiSquareCounts(observed, expected, opts_.alpha, opts_.minExpected, [this](std::size_t c) { return cellName(c); });
        r.samples = n;
        r.badSamples = bad;
        r.pdfIntegral = total;
        r.normTolerance = opts_.normTolerance;
        std::string failure;
        if (bad > 0)
            failure = std::to_string(bad) + " samples are not finite unit vectors, e.g. " + badExample;
        else if (pdfInvalid())
            failure = "the pdf is negative or not finite: " + invalid_;
        else if (!(std::abs(total - 1.0) <= opts_.normTolerance))
            failure = "the pdf integrates to " + std::to_string(total) + " over the sphere, not 1";
        else if (r.zeroCellSamples > 0)
            failure = r.failure + (zeroExample.empty() ? "" : "; " + zeroExample);
        else if (r.dof < opts_.minDof)
            failure = "only " + std::to_string(r.dof) + " degrees of freedom (at least " + std::to_string(opts_.minDof) +
                      " wanted): a finer grid, more samples or a concentration";
        else
            failure = r.failure;
        r.failure = failure;
        r.passed = failure.empty();
        return r;
    }

private:
    static constexpr unsigned char kSawZero = 1, kSawPositive = 2;

    /// Integral of the pdf over a cell, every dimension split into 2^minDepth pieces before the stopping
    /// rule applies; `seen` collects whether the pdf was seen zero and / or positive.
    double integrateCell(int row, int col, int minDepth, unsigned char* seen = nullptr) const {
        const double z0 = edges_[row + 1], z1 = edges_[row], p0 = col * dPhi_, p1 = (col + 1) * dPhi_;
        if (!(z1 > z0)) return 0.0;
        // Inner tolerance scaled so that its error, integrated over the row's height, stays within tolerance.
        const double epsInner = opts_.tolerance / (z1 - z0), epsOuter = opts_.tolerance;
        const auto g = [&](double z) {
            const double sinT = std::sqrt(std::max(0.0, 1.0 - z * z));
            const auto f = [&](double phi) {
                const Vec3 w = frame_.toWorld(Vec3(sinT * std::cos(phi), sinT * std::sin(phi), z));
                const double p = pdf_(w);
                if (!(p >= 0) || !std::isfinite(p)) {
                    if (invalid_.empty())
                        invalid_ = "pdf(" + std::to_string(w.x) + ", " + std::to_string(w.y) + ", " + std::to_string(w.z) +
                                   ") = " + std::to_string(p);
                    return 0.0;
                }
                if (seen) *seen |= p > 0 ? kSawPositive : kSawZero;
                return p;
            };
            return detail::adaptiveSimpson(f, p0, p1, epsInner, minDepth);
        };
        return std::max(0.0, detail::adaptiveSimpson(g, z0, z1, epsOuter, minDepth));
    }

    std::function<double(const Vec3&)> pdf_;
    ChiSquareOptions opts_;
    Frame frame_{};
    int rows_ = 0, cols_ = 0;
    double dPhi_ = 0;
    std::vector<double> edges_, prob_;
    double total_ = 0;
    mutable std::string invalid_;
};

/// One chi-square run: directions `dirs` against `pdf` (header comment).
inline ChiSquareResult chiSquareSphere(const std::vector<Vec3>& dirs, const std::function<double(const Vec3&)>& pdf,
                                       const ChiSquareOptions& opts = {}) {
    return SphereChiSquare(pdf, opts).test(dirs);
}

/// Integral of a non-negative function over the sphere by the grid's adaptive quadrature (the sum of its cells'
/// integrals; opts chooses the grid, e.g. an axis and concentration for a narrow lobe).
/// One run of a TEST of `runs` chi-square runs: alpha = sidakAlpha(runs), so the TEST as a whole rejects
/// a correct sampler with probability 0.01. A GoogleTest expectation; SYMPHONG_CHI2_VERBOSE=1 prints
/// every run's description.
inline void expectChiSquareFits(const std::string& what, const std::vector<Vec3>& dirs, const std::function<double(const Vec3&)>& pdf,
                                ChiSquareOptions opts, int runs) {
    opts.alpha = sidakAlpha(runs);
    const auto r = chiSquareSphere(dirs, pdf, opts);
    EXPECT_TRUE(r.passed) << what << ": " << r.describe();
    if (std::getenv("SYMPHONG_CHI2_VERBOSE")) std::printf("%s: %s\n", what.c_str(), r.describe().c_str());
}

inline double integrateSphereAdaptive(const std::function<double(const Vec3&)>& f, const ChiSquareOptions& opts = {}) {
    return SphereChiSquare(f, opts).pdfIntegral();
}

/// Integral of a density over the sphere by the midpoint rule on a fine (theta, phi) grid (an even
/// thetaRes puts the horizon on a cell edge, where hemispherical densities jump). For an adaptive
/// integral, SphereChiSquare(pdf, opts).pdfIntegral().
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
