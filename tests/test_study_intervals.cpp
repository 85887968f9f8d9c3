// study/intervals.h and study/comparisons.h: Student's t quantile against its closed forms, the efficiency
// ratio's delta-method interval (its coverage of a known ratio over 1000 synthetic studies), the verdicts,
// and the rule that adds repeats (a synthetic estimator of known variance stops at the repeat count that
// the closed form of the interval predicts).
#include "study/comparisons.h"
#include "study/intervals.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <random>

namespace symphong {
namespace {

TEST(StudentQuantile, MatchesItsClosedForms) {
    const double pi = std::acos(-1.0);
    for (double p : {0.6, 0.9, 0.975, 0.995}) {
        EXPECT_NEAR(studentQuantile(p, 1), std::tan(pi * (p - 0.5)), 1e-9) << p;              // Cauchy
        EXPECT_NEAR(studentQuantile(p, 2), (2 * p - 1) / std::sqrt(2 * p * (1 - p)), 1e-9) << p;  // F(t) = 1/2 + t / (2 sqrt(2 + t^2))
        EXPECT_NEAR(studentQuantile(1 - p, 7), -studentQuantile(p, 7), 1e-12);
    }
    EXPECT_NEAR(studentQuantile(0.975, 1000000), 1.959963985, 1e-5);  // the normal limit
    EXPECT_NEAR(studentQuantile(0.975, 4), 2.776445105, 1e-8);          // tables (R: qt(0.975, 4))
    EXPECT_NEAR(studentQuantile(0.975, 29), 2.045229642, 1e-8);
    EXPECT_TRUE(std::isnan(studentQuantile(0.975, 0)));
}

TEST(EfficiencyRatio, IsTheRatioOfMeansWithItsPointInside) {
    // Constant repeats: the ratio exactly, no width.
    auto r = efficiencyRatio({2, 2, 2}, {1, 1, 1}, {4, 4, 4}, {3, 3, 3});
    ASSERT_TRUE(r);
    EXPECT_DOUBLE_EQ(r->point, 6.0);  // (4 x 3) / (2 x 1)
    EXPECT_DOUBLE_EQ(r->lo, 6.0);
    EXPECT_DOUBLE_EQ(r->hi, 6.0);
    EXPECT_EQ(r->n, 3);
    // Means, not medians: one firefly repeat of a costs it its efficiency.
    r = efficiencyRatio({1, 1, 1, 9}, {1, 1, 1, 1}, {1, 1, 1, 1}, {1, 1, 1, 1});
    EXPECT_DOUBLE_EQ(r->point, 1.0 / 3.0);
    EXPECT_LT(r->lo, r->point);
    EXPECT_GT(r->hi, r->point);
    // Swapping the sides inverts the ratio and its interval.
    const std::vector<double> ma = {1.1, 0.9, 1.3, 0.8}, ca = {2, 2.1, 1.9, 2}, mb = {0.7, 0.8, 0.75, 0.9}, cb = {3, 3.2, 2.9, 3.1};
    const auto ab = efficiencyRatio(ma, ca, mb, cb), ba = efficiencyRatio(mb, cb, ma, ca);
    EXPECT_NEAR(ab->point * ba->point, 1.0, 1e-12);
    EXPECT_NEAR(ab->lo * ba->hi, 1.0, 1e-12);
    EXPECT_NEAR(ab->hi * ba->lo, 1.0, 1e-12);
    EXPECT_FALSE(efficiencyRatio({}, {}, {}, {}));
    EXPECT_FALSE(efficiencyRatio({0, 0}, {1, 1}, {1, 1}, {1, 1}));
    EXPECT_FALSE(efficiencyRatio({1}, {1, 1}, {1}, {1}));
    const auto one = efficiencyRatio({2}, {1}, {1}, {1});
    EXPECT_EQ(one->lo, one->hi);
}

// Coverage: synthetic studies of two variants whose renders have known distributions: MSE log-normal
// (sigma 0.3, and a heavier 0.6), the pair correlated (rho 0.5: the same seed), cost with a 5% spread;
// true ratio rho = E[MSE_b] E[cost_b] / (E[MSE_a] E[cost_a]). 1000 intervals each, from 5 and from 10
// repeats (the study's --repeats and a typical stop): at least 93% must cover it (measured here: printed).
TEST(EfficiencyRatio, IntervalCoversTheTrueRatio) {
    struct Case {
        int n;
        double sigma;
    };
    for (const Case k : {Case{5, 0.3}, Case{10, 0.3}, Case{10, 0.6}, Case{20, 0.6}}) {
        std::mt19937_64 rng(20261202 + k.n);
        std::normal_distribution<double> z(0.0, 1.0);
        const double muA = 0.0, muB = 0.4, costA = 2.0, costB = 1.2, rhoPair = 0.5;
        const double truth = (std::exp(muB + k.sigma * k.sigma / 2) * costB) / (std::exp(muA + k.sigma * k.sigma / 2) * costA);
        int covered = 0, inside = 0;
        const int trials = 1000;
        for (int t = 0; t < trials; ++t) {
            std::vector<double> ma(k.n), ca(k.n), mb(k.n), cb(k.n);
            for (int i = 0; i < k.n; ++i) {
                const double z1 = z(rng), z2 = rhoPair * z1 + std::sqrt(1 - rhoPair * rhoPair) * z(rng);
                ma[i] = std::exp(muA + k.sigma * z1);
                mb[i] = std::exp(muB + k.sigma * z2);
                ca[i] = costA * (1 + 0.05 * z(rng));
                cb[i] = costB * (1 + 0.05 * z(rng));
            }
            const auto r = efficiencyRatio(ma, ca, mb, cb);
            covered += r->lo <= truth && truth <= r->hi;
            inside += r->lo <= r->point && r->point <= r->hi;
        }
        const double rate = static_cast<double>(covered) / trials;
        std::printf("n = %d, sigma = %.1f: %.3f of %d nominal-95%% intervals cover the true ratio\n", k.n, k.sigma, rate, trials);
        EXPECT_GE(rate, 0.93) << "n " << k.n << " sigma " << k.sigma;
        EXPECT_LT(rate, 0.99) << "far too wide";
        EXPECT_EQ(inside, trials) << "the point lies inside its interval";
    }
}

// An error that every MSE shares (the reference's own: StudyRow::referenceSd) widens the interval by its closed
// form: with repeats that agree exactly, the half-width on the log scale is 1.96 sd |1/mean(mseA) - 1/mean(mseB)|;
// equal MSEs shift alike and their ratio not at all; without it, nothing changes.
TEST(EfficiencyRatio, ACommonErrorWidensTheIntervalByItsClosedForm) {
    const double z = 1.959963984540054, sd = 0.1;
    auto r = efficiencyRatio({1, 1, 1}, {1, 1, 1}, {4, 4, 4}, {1, 1, 1}, sd);
    ASSERT_TRUE(r);
    EXPECT_DOUBLE_EQ(r->point, 4.0);
    EXPECT_NEAR(std::log(r->hi / r->point), z * sd * (1.0 - 0.25), 1e-12);
    EXPECT_NEAR(std::log(r->point / r->lo), z * sd * (1.0 - 0.25), 1e-12);
    r = efficiencyRatio({2, 2}, {1, 1}, {2, 2}, {3, 3}, sd);  // the same MSE: the shared error cancels in the ratio
    // (2 x 3) / (2 x 1): the ratio exactly
    EXPECT_DOUBLE_EQ(r->lo, 3.0);
    EXPECT_DOUBLE_EQ(r->hi, 3.0);
    r = efficiencyRatio({1}, {1}, {4}, {1}, sd);  // one repeat: the shared error is the whole interval
    EXPECT_NEAR(std::log(r->hi / r->point), z * sd * 0.75, 1e-12);
    // Spread repeats: the two half-widths add in quadrature.
    const std::vector<double> ma = {1.1, 0.9, 1.3, 0.8}, ca = {2, 2.1, 1.9, 2}, mb = {0.7, 0.8, 0.75, 0.9}, cb = {3, 3.2, 2.9, 3.1};
    const auto alone = efficiencyRatio(ma, ca, mb, cb), both = efficiencyRatio(ma, ca, mb, cb, sd);
    const double hRepeats = std::log(alone->hi / alone->point), hCommon = z * sd * std::abs(1 / 1.025 - 1 / 0.7875);
    EXPECT_NEAR(std::log(both->hi / both->point), std::hypot(hRepeats, hCommon), 1e-12);
    EXPECT_DOUBLE_EQ(both->point, alone->point);
}

// Coverage with a noisy reference: synthetic studies of images, not of MSE values. Every trial draws one
// reference (the truth plus Gaussian noise of a variance that differs from pixel to pixel, 2 to 6 times the
// variance of variant a's renders), then n paired repeats of a (variance 1) and b (variance 10), measured as
// the study measures them: mean squared difference to the reference less the reference's mean variance,
// floored at 5% (study/measure.cpp). The reference's realized error is common to every render of the trial;
// with its standard deviation (sqrt(2 sum sigma^4) / P, Reference::noiseSd) at least 93% of 1000 nominal-95%
// intervals cover the true ratio; without it, far fewer (the repeats cannot see an error they all share).
TEST(EfficiencyRatio, IntervalWithTheReferencesErrorCoversTheTrueRatio) {
    const int P = 400, trials = 1000;
    std::vector<double> truth(P), refVariance(P);
    double noise = 0, fourth = 0;
    for (int p = 0; p < P; ++p) {
        truth[p] = 0.5 + 0.3 * std::sin(0.1 * p);
        refVariance[p] = 4.0 * (0.5 + 0.5 * (p % 3));  // 2, 4, 6
        noise += refVariance[p] / P;
        fourth += refVariance[p] * refVariance[p];
    }
    const double noiseSd = std::sqrt(2 * fourth) / P, varA = 1.0, varB = 10.0, costA = 2.0, costB = 1.0;
    const double trueRatio = (varB * costB) / (varA * costA);
    for (const int n : {6, 12}) {
        std::mt19937_64 rng(20261206 + n);
        std::normal_distribution<double> g(0.0, 1.0);
        int coveredWith = 0, coveredWithout = 0;
        std::vector<double> ref(P);
        for (int t = 0; t < trials; ++t) {
            for (int p = 0; p < P; ++p) ref[p] = truth[p] + std::sqrt(refVariance[p]) * g(rng);
            std::vector<double> ma(n), ca(n), mb(n), cb(n);
            const auto measured = [&](double variance) {
                double raw = 0;
                for (int p = 0; p < P; ++p) {
                    const double d = truth[p] + std::sqrt(variance) * g(rng) - ref[p];
                    raw += d * d / P;
                }
                return std::max(raw - noise, 0.05 * raw);
            };
            for (int i = 0; i < n; ++i) {
                ma[i] = measured(varA), mb[i] = measured(varB);
                ca[i] = costA * (1 + 0.05 * g(rng)), cb[i] = costB * (1 + 0.05 * g(rng));
            }
            const auto with = efficiencyRatio(ma, ca, mb, cb, noiseSd), without = efficiencyRatio(ma, ca, mb, cb);
            coveredWith += with->lo <= trueRatio && trueRatio <= with->hi;
            coveredWithout += without->lo <= trueRatio && trueRatio <= without->hi;
        }
        const double rateWith = static_cast<double>(coveredWith) / trials, rateWithout = static_cast<double>(coveredWithout) / trials;
        std::printf("n = %d: %.3f of %d intervals cover the true ratio with the reference's error, %.3f without\n", n, rateWith, trials,
                    rateWithout);
        EXPECT_GE(rateWith, 0.93) << n;
        EXPECT_LE(rateWith, 0.995) << n << ": far too wide";
        EXPECT_LT(rateWithout, 0.85) << n << ": the test's reference is not noisy enough to show anything";
    }
}

TEST(Verdict, AheadBehindEqualOrNotResolved) {
    EXPECT_EQ(verdictOf({1.3, 1.1, 1.5, 5}), Verdict::Ahead);
    EXPECT_EQ(verdictOf({0.7, 0.6, 0.8, 5}), Verdict::Behind);
    EXPECT_EQ(verdictOf({1.0, 0.93, 1.08, 5}), Verdict::Equal);
    EXPECT_EQ(verdictOf({1.04, 1.01, 1.07, 5}), Verdict::Equal) << "within 10% counts as equal even when surely ahead";
    EXPECT_EQ(verdictOf({1.0, 0.8, 1.2, 5}), Verdict::Unresolved);
    EXPECT_EQ(verdictOf({1.05, 0.95, 1.15, 5}), Verdict::Unresolved);
    EXPECT_EQ(verdictName(Verdict::Unresolved), "not resolved");
    EXPECT_TRUE(settled({1.3, 1.2, 1.4, 8}, 0.1));
    EXPECT_FALSE(settled({1.3, 1.2, 1.4, 8}, 0.05)) << "half-width 7.7% of the ratio";
    EXPECT_FALSE(settled({1.0, 0.8, 1.2, 8}, 0.5)) << "narrow enough, but says nothing";
    EXPECT_EQ(intervalText({1.234, 0.9, 1.5, 5}), "1.2x [0.90, 1.50]");
    EXPECT_EQ(intervalText({12.3, 12.3, 12.3, 1}), "12x");
}

StudyRow syntheticRow(const std::string& variant, int repeat, double mse, double cost) {
    StudyRow r;
    r.variant = variant;
    r.estimator = variant;
    r.spp = 16;
    r.repeat = repeat;
    r.mse = r.relMse = mse;
    r.cost = cost;
    return r;
}

// Repeats until settled: the yardstick renders exactly (MSE 1, cost 1), variant `near` has MSE 1 +- 0.2
// alternately (ratio 1: settled once its interval lies inside [0.9, 1.1] with half-width <= H) and `far`
// MSE 0.5 (1 +- 0.1) (ratio 2). At an even count n the MSE's mean is exactly its centre and the sample
// deviation of z is sigma sqrt(n / (n - 1)), so the interval is exp(+-h), h = t_{0.975, n-1} sigma / sqrt(n - 1):
// the closed form gives the first n at which it is settled. The planner's rounds must stop there, +-1.
TEST(RepeatsUntilSettled, StopsWhereTheClosedFormSays) {
    const double H = 0.05;
    const auto mseOf = [](const std::string& v, int i) {
        const double s = i % 2 ? -1.0 : 1.0;
        return v == "near" ? 1 + 0.2 * s : v == "far" ? 0.5 * (1 + 0.1 * s) : 1.0;
    };
    const auto predicted = [&](double sigma, bool needEqualBand) {
        for (int n = 2;; n += 2) {
            const double h = studentQuantile(0.975, n - 1) * sigma / std::sqrt(n - 1.0);
            if (std::sinh(h) <= H && (!needEqualBand || h <= std::log(1.1))) return n;  // sinh: (e^h - e^-h) / 2
        }
    };
    const std::vector<VariantPair> comparisons = {{"near", "yard", false, 0}, {"far", "yard", false, 0}};
    std::vector<StudyRow> rows;
    std::map<std::string, int> count;
    for (const std::string v : {"yard", "near", "far"})
        for (int i = 0; i < 2; ++i) rows.push_back(syntheticRow(v, count[v]++, mseOf(v, i), 1.0));
    for (int round = 0; round < 1000; ++round) {
        const std::set<std::string> need = variantsToRepeat(rows, 16, comparisons, H);
        if (need.empty()) break;
        for (const std::string& v : need) {
            const int i = count[v]++;
            rows.push_back(syntheticRow(v, i, mseOf(v, i), 1.0));
        }
    }
    const int nearN = predicted(0.2, true), farN = predicted(0.1, false);
    std::printf("near: %d repeats (closed form %d), far: %d (closed form %d), yardstick %d\n", count["near"], nearN, count["far"], farN,
                count["yard"]);
    EXPECT_NEAR(count["near"], nearN, 1);
    EXPECT_NEAR(count["far"], farN, 1);
    EXPECT_EQ(count["yard"], std::max(count["near"], count["far"])) << "the yardstick renders while any comparison needs it";
    EXPECT_TRUE(variantsToRepeat(rows, 16, comparisons, H).empty());
}

// The reference's own error is in the answer's interval but does not keep the study adding repeats, which
// cannot narrow it: `far` (MSE 0.5 +- 10%) against an exact yardstick stops at the closed form's count with or
// without a shared error of sd 0.05 in every row, while its interval with that error stays wider than the
// target (1.96 x 0.05 x |1/0.5 - 1/1| = 0.098 on the log scale, above log(1.05)).
TEST(RepeatsUntilSettled, TheReferencesErrorDoesNotKeepAddingRepeats) {
    const double H = 0.05;
    const std::vector<VariantPair> comparisons = {{"far", "yard", false, 0}};
    std::map<double, int> repeatsAt;  // by the rows' reference error
    for (const double sd : {0.0, 0.05}) {
        std::vector<StudyRow> rows;
        std::map<std::string, int> count;
        const auto add = [&](const std::string& v) {
            const int i = count[v]++;
            rows.push_back(syntheticRow(v, i, v == "far" ? 0.5 * (1 + 0.1 * (i % 2 ? -1.0 : 1.0)) : 1.0, 1.0));
            rows.back().referenceSd = sd;
        };
        for (int i = 0; i < 2; ++i) add("yard"), add("far");
        for (int round = 0; round < 1000; ++round) {
            const std::set<std::string> need = variantsToRepeat(rows, 16, comparisons, H);
            if (need.empty()) break;
            for (const std::string& v : need) add(v);
        }
        repeatsAt[sd] = count["far"];
        const auto full = compareVariants(rows, "far", "yard", 16);
        const auto repeats = compareVariants(rows, "far", "yard", 16, ErrorMeasure::Mse, ReferenceError::Left);
        EXPECT_TRUE(settled(*repeats, H)) << sd;
        EXPECT_EQ(settled(*full, H), sd == 0) << sd << ": " << intervalText(*full);
        if (sd > 0) {
            EXPECT_GT(std::log(full->hi / full->point), 1.959963984540054 * sd * 1.0 - 1e-12);
        }
    }
    EXPECT_EQ(repeatsAt[0.05], repeatsAt[0.0]) << "repeats are not spent on an error they cannot narrow";
    EXPECT_LT(repeatsAt[0.0], 100);
}

TEST(RepeatsUntilSettled, BiasedVariantsAreNotWaitedFor) {
    std::vector<StudyRow> rows;
    for (int i = 0; i < 3; ++i) {
        rows.push_back(syntheticRow("yard", i, 1.0, 1.0));
        rows.push_back(syntheticRow("paper", i, i + 1.0, 1.0));
        rows.back().groupBiasSignificant = true;
    }
    EXPECT_TRUE(variantsToRepeat(rows, 16, {{"paper", "yard", false, 0}}, 0.01).empty());
    rows.back().groupBiasSignificant = false;
    for (auto& r : rows) r.groupBiasSignificant = false;
    EXPECT_EQ(variantsToRepeat(rows, 16, {{"paper", "yard", false, 0}}, 0.01), (std::set<std::string>{"paper", "yard"}));
}

TEST(Comparisons, PairsTheRepeatsByNumber) {
    std::vector<StudyRow> rows = {syntheticRow("a", 0, 1, 1), syntheticRow("a", 1, 3, 1), syntheticRow("a", 2, 100, 1),
                                  syntheticRow("b", 1, 6, 1), syntheticRow("b", 0, 2, 1)};
    const auto r = compareVariants(rows, "a", "b", 16);
    ASSERT_TRUE(r);
    EXPECT_EQ(r->n, 2) << "repeat 2 of a has no partner";
    EXPECT_DOUBLE_EQ(r->point, 2.0);  // mean(2, 6) / mean(1, 3)
    EXPECT_FALSE(compareVariants(rows, "a", "c", 16));
}

}  // namespace
}  // namespace symphong
