// study/intervals.h — the statistics of the study's answer: how much more efficient one variant is than
// another, with a 95% interval from paired repeats, and what that interval says (ahead, behind, equal).
//
// Efficiency is 1/(MSE x cost). Of a variant it is 1/(E[MSE] E[cost]); the ratio of a over b,
// rho = E[MSE_b] E[cost_b] / (E[MSE_a] E[cost_a]), is estimated by the ratio of the sample means over the
// repeats both have (repeat r of each with the same seed: pairs). Its interval is the delta method on
// log rho-hat: with z_r = MSE_b,r / mean(MSE_b) + cost_b,r / mean(cost_b) - MSE_a,r / mean(MSE_a) -
// cost_a,r / mean(cost_a), the first-order variance of log rho-hat is var(z) / n (the pairs' covariances
// included), and the interval is rho-hat x exp(+-t_{0.975, n-1} sd(z) / sqrt(n)). It lies around the
// point on the log scale, so the point is always inside it. Picked over the percentile bootstrap of
// ratio of medians that the study used before by the coverage test in tests/test_study_intervals.cpp
// (synthetic renders with known MSE and cost distributions: at least 93% of 1000 nominal-95% intervals
// cover the true ratio, from 5 repeats up).
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace symphong {

/// A ratio with its 95% interval, from `n` pairs (0: not from repeats).
struct RatioInterval {
    double point = 0, lo = 0, hi = 0;
    int n = 0;
    /// Half the interval's width over the point: the interval's relative half-width.
    double relativeHalfWidth() const { return point > 0 ? 0.5 * (hi - lo) / point : 0.0; }
};

/// The p-quantile of Student's t distribution with `dof` degrees of freedom (p in (0, 1), dof >= 1), from its
/// distribution function (the regularized incomplete beta function) by bisection.
double studentQuantile(double p, int dof);

/// The efficiency ratio of a over b, (mean(mseB) mean(costB)) / (mean(mseA) mean(costA)), over paired
/// repeats (element r of each vector is repeat r; all four of one length n), with its 95% interval by the
/// delta method (above). Nothing when n is 0 or a mean is not > 0; with n = 1 the interval is the point.
///
/// `commonSd`: the standard deviation of an error that every MSE of the study shares, which no number of
/// repeats averages away: the reference's own (the realized noise of one reference image, less the mean
/// noise that study/measure.cpp removes; Reference::noiseSd). An error d common to both moves log rho-hat by
/// about d (1/mean(mseA) - 1/mean(mseB)); its 95% half-width, 1.96 commonSd |1/mean(mseA) - 1/mean(mseB)|,
/// joins the repeats' t half-width in quadrature. It weighs most where one variant's MSE is small beside the
/// reference's noise; with n = 1 it is the whole interval.
std::optional<RatioInterval> efficiencyRatio(const std::vector<double>& mseA, const std::vector<double>& costA,
                                             const std::vector<double>& mseB, const std::vector<double>& costB, double commonSd = 0);

/// The mean of `values` and its 95% interval, mean +- t sd / sqrt(n) (lo at least 0 for values >= 0).
RatioInterval meanInterval(const std::vector<double>& values);

/// What an efficiency ratio's interval says of a against b.
enum class Verdict {
    Ahead,       ///< the whole interval above 1
    Behind,      ///< the whole interval below 1
    Equal,       ///< the whole interval inside [1 - band, 1 + band] (before ahead and behind)
    Unresolved,  ///< none of these
};

/// The band within which two variants count as equal: 10%.
inline constexpr double kEqualBand = 0.1;

Verdict verdictOf(const RatioInterval& r, double band = kEqualBand);
/// "ahead", "behind", "equal", "not resolved".
std::string verdictName(Verdict v);

/// Whether a ratio is settled at the target: its interval says ahead, behind or equal, and its relative
/// half-width is at most `target`.
bool settled(const RatioInterval& r, double target);

/// "1.2x [0.95, 1.50]"; the point alone when the interval has no width.
std::string intervalText(const RatioInterval& r);

}  // namespace symphong
