// The factors that the study's answer quotes in its "Most efficient by MSE / relMSE" lines, read back from
// the line's text, and the same factors computed again from rows by the definition (study/intervals.h),
// independently of the study's code: efficiency 1/(E[error] E[cost]); the ratio of a over b is
// mean(error_b) mean(cost_b) / (mean(error_a) mean(cost_a)) over the repeats both have; its 95% interval
// rho exp(+-t sd(z) / sqrt(n)), z_r = error_b,r / mean(error_b) + cost_b,r / mean(cost_b) - error_a,r /
// mean(error_a) - cost_a,r / mean(cost_a), with Student's t quantile from its closed forms for 1 and 2
// degrees of freedom (the repeats of the tests that use this); by MSE, joined in quadrature by 1.96 sd |1 /
// mean(error_a) - 1 / mean(error_b)|, sd the reference's own error that every MSE shares (its noise_sd).
// Used by test_study.cpp (from results.csv) and test_study_answer.cpp (from rows made by hand).
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>
#include <optional>
#include <regex>
#include <string>
#include <vector>

namespace answer_factors {

/// A factor as printed: "1.2x [0.95, 1.50]" against a variant.
struct Quoted {
    std::string against;
    double point = 0, lo = 0, hi = 0;
};

/// The line's best variant and its factors against the next and, when quoted, against the yardstick.
struct Line {
    std::string best;
    std::vector<Quoted> factors;
};

/// Reads "**Most efficient by M** at N spp: `best`, F [lo, hi] the efficiency of the next, `next`[, F [lo, hi]
/// that of `yard`]." Nothing when the line is not of that form.
inline std::optional<Line> parseMostEfficient(const std::string& text) {
    static const std::regex head(R"(^\*\*Most efficient by (MSE|relMSE)\*\* at \d+ spp: `([^`]+)`)");
    static const std::regex factor(R"(, ([0-9.]+)x \[([0-9.]+), ([0-9.]+)\] (?:the efficiency of the next,|that of) `([^`]+)`)");
    std::smatch m;
    if (!std::regex_search(text, m, head)) return std::nullopt;
    Line line{m[2], {}};
    for (std::sregex_iterator it(text.begin(), text.end(), factor), end; it != end; ++it)
        line.factors.push_back({(*it)[4], std::stod((*it)[1]), std::stod((*it)[2]), std::stod((*it)[3])});
    return line;
}

/// One render's numbers: its repeat, error by the measure in question, and cost.
struct Sample {
    int repeat = 0;
    double error = 0, cost = 0;
};

/// t_{0.975, dof} for dof 1 (tan(0.475 pi), the Cauchy quantile) and 2 ((2p - 1) / sqrt(2 p (1 - p))).
inline double t975(int dof) {
    if (dof == 1) return std::tan(0.475 * std::numbers::pi);
    if (dof == 2) return 0.95 / std::sqrt(2 * 0.975 * 0.025);
    ADD_FAILURE() << "no closed form here for " << dof << " degrees of freedom";
    return NAN;
}

/// The efficiency ratio of a over b with its interval, over their common repeats; `commonSd`: an error that
/// both sides' errors share (the reference's, by MSE).
inline Quoted ratio(const std::vector<Sample>& a, const std::vector<Sample>& b, double commonSd = 0) {
    std::map<int, Sample> byRepeat;
    for (const Sample& s : b) byRepeat[s.repeat] = s;
    std::vector<Sample> pa, pb;
    for (const Sample& s : a)
        if (byRepeat.count(s.repeat)) pa.push_back(s), pb.push_back(byRepeat[s.repeat]);
    const double n = static_cast<double>(pa.size());
    double ea = 0, ca = 0, eb = 0, cb = 0;
    for (std::size_t i = 0; i < pa.size(); ++i) ea += pa[i].error / n, ca += pa[i].cost / n, eb += pb[i].error / n, cb += pb[i].cost / n;
    Quoted q;
    q.point = eb * cb / (ea * ca);
    std::vector<double> z;
    double zm = 0;
    for (std::size_t i = 0; i < pa.size(); ++i) {
        z.push_back(pb[i].error / eb + pb[i].cost / cb - pa[i].error / ea - pa[i].cost / ca);
        zm += z.back() / n;
    }
    double ss = 0;
    for (double x : z) ss += (x - zm) * (x - zm);
    const double repeats = t975(static_cast<int>(n) - 1) * std::sqrt(ss / (n - 1)) / std::sqrt(n);
    const double shared = 1.959963984540054 * commonSd * std::abs(1 / ea - 1 / eb);
    const double h = std::sqrt(repeats * repeats + shared * shared);
    q.lo = q.point * std::exp(-h);
    q.hi = q.point * std::exp(h);
    return q;
}

/// The printed factor agrees with the computed one to the digits printed: the point to two significant
/// digits, the bounds to two decimals (three significant digits from 10 up).
inline void expectQuotes(const Quoted& printed, const Quoted& computed, const std::string& what) {
    const auto digit = [](double x, int significant) { return 0.5 * std::pow(10.0, std::floor(std::log10(std::abs(x))) - (significant - 1)); };
    const auto bound = [&](double x) { return x < 10 ? 0.005 : digit(x, 3); };
    EXPECT_NEAR(printed.point, computed.point, (computed.point >= 10 ? 0.5 : digit(computed.point, 2)) * 1.0001) << what;
    EXPECT_NEAR(printed.lo, computed.lo, bound(computed.lo) * 1.0001) << what;
    EXPECT_NEAR(printed.hi, computed.hi, bound(computed.hi) * 1.0001) << what;
}

}  // namespace answer_factors
