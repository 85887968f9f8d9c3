// Efficiency-aware Russian roulette and splitting (splitting/, --splitting ears): the factor's rules,
// its fixed point against the closed-form optimum and a brute-force minimum of variance x cost, exact
// sums in any order, the epoch schedule, the split directions against the estimator's density
// (chi-square), unbiasedness (the closed furnace, and the mean image against phong on every study
// scene, 4 sigma), determinism across threads and passes, a checkpoint's round trip, and bad values.
#include "ears_settings.h"
#include "render/checkpoint.h"
#include "render/settings.h"
#include "sample_util.h"
#include "sampling/warp.h"
#include "stats.h"
#include "test_util.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <optional>
#include <random>

using namespace symphong;
using symphong::test::earsSettings;
using symphong::test::sameBits;

TEST(EarsFactor, SplitsByVarianceRoulettesBySecondMomentAndClamps) {
    // q_split = T sqrt(v/C_x) sqrt(C/V) = 2 x 1 x 1 > 1: split by it.
    EXPECT_DOUBLE_EQ(ears::splittingFactor(2, 1, 3, 1), 2);
    // q_split = 0.25, q_rr = 0.75: roulette by the second moment.
    EXPECT_DOUBLE_EQ(ears::splittingFactor(0.5, 0.5, 1.5, 1), 0.75);
    // q_split = 0.5 <= 1 <= q_rr = 2: the two disagree, one continuation.
    EXPECT_DOUBLE_EQ(ears::splittingFactor(1, 0.5, 2, 1), 1);
    EXPECT_DOUBLE_EQ(ears::splittingFactor(100, 1, 1, 1), ears::kMaxFactor);
    EXPECT_DOUBLE_EQ(ears::splittingFactor(1e-4, 1, 1, 1), ears::kMinFactor);
    EXPECT_DOUBLE_EQ(ears::splittingFactor(std::nan(""), 1, 1, 1), ears::kMinFactor);
    EXPECT_DOUBLE_EQ(ears::splittingFactor(1, 0, 0, 1), ears::kMinFactor);  // a region that never brings light back
}

// The factor is computed by selects, not branches: the same as the rule read case by case (EARS's: split by
// q_split above 1, else roulette by q_rr below 1, else 1; then clamped), on random inputs that include a
// sample variance above the second moment (n / (n - 1) makes that possible when the mean is small).
TEST(EarsFactor, TheSelectsGiveTheRuleCaseByCase) {
    const auto rule = [](double t, double vr, double mr, double s) {
        const double split = t * vr * s, roulette = t * mr * s;
        double q = 1;
        if (split > 1)
            q = split;
        else if (roulette < 1)
            q = roulette;
        return std::min(std::max(q, ears::kMinFactor), ears::kMaxFactor);
    };
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> logValue(std::log(1e-3), std::log(1e2));
    int split = 0, roulette = 0, one = 0;
    for (int i = 0; i < 100000; ++i) {
        const double t = std::exp(logValue(rng)), vr = std::exp(logValue(rng)), mr = std::exp(logValue(rng)), s = std::exp(logValue(rng));
        const double q = ears::splittingFactor(t, vr, mr, s);
        ASSERT_EQ(q, rule(t, vr, mr, s)) << t << " " << vr << " " << mr << " " << s;
        split += t * vr * s > 1, roulette += t * vr * s <= 1 && t * mr * s < 1, one += t * vr * s <= 1 && t * mr * s >= 1;
    }
    EXPECT_GT(split, 1000);  // every case met often
    EXPECT_GT(roulette, 1000);
    EXPECT_GT(one, 1000);
    // And the floor is the larger of the two factors whenever plain's survival is below 1, as it always is.
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (int i = 0; i < 10000; ++i) {
        const double q = 3 * u(rng), plain = ears::throughputSurvival(2 * u(rng));
        ASSERT_EQ(ears::flooredRoulette(q, plain), q < 1 ? std::max(q, plain) : q);
    }
}

// Plain roulette's survival (the factor of an unlearned deeper vertex) and the floor that a low-discrepancy
// sampler puts under a learned roulette factor: roulette no harsher than plain's, splitting untouched.
TEST(EarsFactor, RouletteFloorIsPlainRoulettesSurvival) {
    EXPECT_DOUBLE_EQ(ears::throughputSurvival(0.4), 0.4);
    EXPECT_DOUBLE_EQ(ears::throughputSurvival(3.0), 0.95);
    EXPECT_DOUBLE_EQ(ears::throughputSurvival(1e-6), ears::kMinFactor);
    EXPECT_DOUBLE_EQ(ears::throughputSurvival(std::nan("")), ears::kMinFactor);
    EXPECT_DOUBLE_EQ(ears::flooredRoulette(0.1, 0.5), 0.5);   // EARS's roulette harsher: plain's
    EXPECT_DOUBLE_EQ(ears::flooredRoulette(0.7, 0.3), 0.7);   // gentler: its own
    EXPECT_DOUBLE_EQ(ears::flooredRoulette(2.5, 0.95), 2.5);  // splitting: unchanged
    EXPECT_DOUBLE_EQ(ears::flooredRoulette(1.0, 0.95), 1.0);
}

// Two regions with known variance and cost: the fixed point of q <- T sqrt(v/C_x) sqrt(C(q)/V(q)), iterated
// as a render does from epoch to epoch, equals the analytic optimum sqrt(C0/V0) T sqrt(v/C_x) (from
// d(V C)/dq = 0 for every region: sum over regions cancels and s^2 V0 = C0), and a brute-force search of
// V x C over a fine grid of (q1, q2) finds no lower point.
TEST(EarsFixedPoint, EqualsTheAnalyticOptimumAndTheBruteForceMinimum) {
    const double v0 = 1, c0 = 3;
    const std::vector<ears::ModelRegion> regions = {{1, 1, 4, 2}, {2, 0.3, 0.5, 5}};
    const std::vector<double> q = ears::modelFixedPoint(v0, c0, regions, 60);
    for (std::size_t r = 0; r < regions.size(); ++r) {
        const double exact = std::sqrt(c0 / v0) * regions[r].throughput * std::sqrt(regions[r].variance / regions[r].cost);
        EXPECT_NEAR(q[r], exact, 1e-9 * exact) << "region " << r;
    }
    EXPECT_GT(q[0], 1);  // one region splits, the other is rouletted: both branches of the rule are used
    EXPECT_LT(q[1], 1);
    double v = 0, c = 0;
    ears::modelVarianceAndCost(v0, c0, regions, q, v, c);
    const double atFixedPoint = v * c;
    double best = std::numeric_limits<double>::infinity(), bestQ1 = 0, bestQ2 = 0;
    const int steps = 1500;
    const auto grid = [&](int i) { return ears::kMinFactor * std::pow(ears::kMaxFactor / ears::kMinFactor, i / double(steps)); };
    for (int i = 0; i <= steps; ++i)
        for (int j = 0; j <= steps; ++j) {
            ears::modelVarianceAndCost(v0, c0, regions, {grid(i), grid(j)}, v, c);
            if (v * c < best) best = v * c, bestQ1 = grid(i), bestQ2 = grid(j);
        }
    EXPECT_LE(atFixedPoint, best * (1 + 1e-12));
    const double step = std::pow(ears::kMaxFactor / ears::kMinFactor, 1.0 / steps);  // one grid step, as a factor
    EXPECT_NEAR(std::log(bestQ1 / q[0]), 0, std::log(step));
    EXPECT_NEAR(std::log(bestQ2 / q[1]), 0, std::log(step));
}

TEST(EarsSums, AreTheSameBitForBitInAnyOrderAndMatchTheMoments) {
    std::mt19937_64 rng(7);
    std::vector<std::pair<double, std::uint64_t>> records;
    long double sum = 0, sumSq = 0, cost = 0;
    for (int i = 0; i < 20000; ++i) {
        const double v = std::pow(10.0, std::uniform_real_distribution<double>(-6, 4)(rng));
        const std::uint64_t rays = 1 + rng() % 9;
        records.push_back({v, rays});
        sum += v, sumSq += static_cast<long double>(v) * v, cost += rays;
    }
    ears::CellSums inOrder, shuffled;
    for (const auto& [v, r] : records) inOrder.add(v, r);
    std::shuffle(records.begin(), records.end(), rng);
    std::vector<ears::CellSums> parts(7);
    for (std::size_t i = 0; i < records.size(); ++i) parts[i % 7].add(records[i].first, records[i].second);
    for (const ears::CellSums& p : parts) shuffled.add(p);
    EXPECT_EQ(std::memcmp(&inOrder, &shuffled, sizeof inOrder), 0);
    const double n = static_cast<double>(records.size());
    EXPECT_NEAR(inOrder.mean(), static_cast<double>(sum / n), 1e-9 * static_cast<double>(sum / n));
    EXPECT_NEAR(inOrder.secondMoment(), static_cast<double>(sumSq / n), 1e-9 * static_cast<double>(sumSq / n));
    EXPECT_DOUBLE_EQ(inOrder.meanCost(), static_cast<double>(cost / n));
}

// A CellSet visits what it holds in increasing order, within any range (bounds inside a word too), and
// holds nothing after clear().
TEST(EarsCellSet, VisitsItsCellsInOrderWithinAnyRange) {
    ears::CellSet set(1000);
    const std::vector<std::size_t> cells = {0, 1, 63, 64, 65, 127, 128, 500, 511, 512, 998, 999};
    for (auto it = cells.rbegin(); it != cells.rend(); ++it) set.insert(*it);
    set.insert(64);  // twice: still once
    for (const auto& [from, to] : std::vector<std::pair<std::size_t, std::size_t>>{{0, 1000}, {1, 64}, {63, 66}, {66, 127}, {128, 999}, {500, 500}, {0, 5000}}) {
        std::vector<std::size_t> seen, expected;
        set.forEach(from, to, [&](std::size_t c) { seen.push_back(c); });
        for (std::size_t c : cells)
            if (c >= from && c < to) expected.push_back(c);
        EXPECT_EQ(seen, expected) << "[" << from << ", " << to << ")";
    }
    EXPECT_TRUE(set.contains(999));
    EXPECT_FALSE(set.contains(2));
    EXPECT_FALSE(set.contains(5000));
    set.clear();
    std::size_t left = 0;
    set.forEach(0, 1000, [&](std::size_t) { ++left; });
    EXPECT_EQ(left, 0u);
}

// The end of an epoch visits only the cells that records reached (Learning keeps them in a CellSet):
// its factors equal, bit for bit, those learned from a scan of the whole table (propagateToCoarserCells
// and learnFactors without a set: the second method), epoch after epoch, and every cell, the coarser
// ones that the carrying-up filled included, is empty again afterwards.
TEST(EarsLearn, TheCellsRecordsReachedAreAllTheEpochsEndVisits) {
    const ears::Grid grid(Vec3(-1, -1, -1), Vec3(1, 1, 1));
    ears::Learning l(grid);
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(-1, 1);
    std::uint64_t rays = 0, samples = 0;
    for (int epoch = 0; epoch < 3; ++epoch) {
        // Records on a few surfaces (two planes and a sphere), in every section, some cells with few.
        std::vector<ears::Record> records;
        for (int i = 0; i < 60000; ++i) {
            Vec3 p(u(rng), u(rng), u(rng));
            if (i % 3 == 0) p.y = -0.9;
            else if (i % 3 == 1) p.x = 0.3 * epoch - 0.5;
            else p = normalize(p) * 0.4;
            const auto cell = static_cast<std::uint32_t>(grid.cell(p, ears::Grid::kLevels - 1));
            const auto section = static_cast<ears::Section>(i % ears::kSections);
            records.emplace_back(cell, std::pow(u(rng) + 1.0, 3), 1 + rng() % 5, section);
        }
        for (std::size_t i = 0; i < records.size(); i += 5000)
            l.add(std::vector<ears::Record>(records.begin() + static_cast<long>(i), records.begin() + static_cast<long>(std::min(records.size(), i + 5000))));
        l.add(records.front());
        rays += 400000, samples += 50000;
        ears::SumTable scanned = l.sums();
        ears::propagateToCoarserCells(scanned);
        const std::uint64_t epochSamples = samples - l.samplesAtStart, epochRays = rays - l.raysAtStart;
        const double variance = 0.5 + epoch, measured = epoch == 0 ? variance : std::max(2 * variance - l.varianceAtStart, 0.25 * variance);
        const ears::Factors expected = ears::learnFactors(
            scanned, {static_cast<double>(epochRays) / static_cast<double>(epochSamples), measured, static_cast<double>(epochSamples)});
        ASSERT_FALSE(expected.empty());
        l.advance(variance, rays, samples);
        ASSERT_EQ(l.factors.momentRatio.size(), expected.momentRatio.size());
        EXPECT_EQ(std::memcmp(l.factors.momentRatio.data(), expected.momentRatio.data(), expected.momentRatio.size() * sizeof(float)), 0);
        EXPECT_EQ(std::memcmp(l.factors.varianceRatio.data(), expected.varianceRatio.data(), expected.varianceRatio.size() * sizeof(float)), 0);
        EXPECT_EQ(std::memcmp(l.factors.firstHit.data(), expected.firstHit.data(), expected.firstHit.size() * sizeof(float)), 0);
        EXPECT_EQ(l.factors.scale, expected.scale);
        EXPECT_GT(std::count_if(expected.firstHit.begin(), expected.firstHit.end(), [](float q) { return q >= 1; }), 100);
        EXPECT_TRUE(std::all_of(l.sums().begin(), l.sums().end(), [](const ears::CellSums& c) { return c.empty(); }));
    }
}

// The first hit's number of continuations: the power of two nearest the model's q on a log scale, which is
// the brute-force best power of two for the model's a / n + b n (its ratio to the minimum, q/n + n/q).
TEST(EarsFactor, FirstHitBlocksAreTheBestPowerOfTwo) {
    EXPECT_EQ(ears::firstHitBlock(1.0), 1.0);
    EXPECT_EQ(ears::firstHitBlock(1.41), 1.0);
    EXPECT_EQ(ears::firstHitBlock(1.42), 2.0);
    EXPECT_EQ(ears::firstHitBlock(5.6), 4.0);
    EXPECT_EQ(ears::firstHitBlock(5.7), 8.0);
    EXPECT_EQ(ears::firstHitBlock(100.0), 8.0);
    EXPECT_EQ(ears::firstHitBlock(0.3), 1.0);
    EXPECT_EQ(ears::firstHitBlock(std::nan("")), 1.0);
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> logQ(0.0, std::log(ears::kMaxFactor));
    for (int i = 0; i < 10000; ++i) {
        const double q = std::exp(logQ(rng));
        double best = 1, bestCost = 1e300;
        for (double n : {1.0, 2.0, 4.0, 8.0})
            if (const double cost = q / n + n / q; cost < bestCost) best = n, bestCost = cost;
        ASSERT_EQ(ears::firstHitBlock(q), best) << "q " << q;
    }
}

TEST(EarsSchedule, EpochsDoubleAfterTheFirstTwoSamples) {
    const std::uint32_t samples[] = {0, 1, 2, 3, 4, 7, 8, 15, 16, 1000};
    const int epochs[] = {0, 0, 1, 1, 2, 2, 3, 3, 4, 9};
    const std::uint32_t ends[] = {2, 2, 4, 4, 8, 8, 16, 16, 32, 1024};
    for (std::size_t i = 0; i < std::size(samples); ++i) {
        EXPECT_EQ(ears::epochOf(samples[i]), epochs[i]) << samples[i];
        EXPECT_EQ(ears::epochEnd(samples[i]), ends[i]) << samples[i];
        EXPECT_LE(ears::epochStart(epochs[i]), samples[i]);
        EXPECT_EQ(ears::epochEnd(ears::epochStart(epochs[i])), ends[i]);
    }
}

TEST(EarsGrid, EveryLevelCoversTheBoxAndTheFinestKnownCellIsChosen) {
    const ears::Grid grid(Vec3(-1, 0, 2), Vec3(1, 4, 3));
    EXPECT_EQ(ears::Grid::cellCount(), 4u * 4 * 4 + 8u * 8 * 8 + 16u * 16 * 16 + 32u * 32 * 32);
    std::size_t first = 0;
    for (int level = 0; level < ears::Grid::kLevels; ++level) {
        const std::size_t r = static_cast<std::size_t>(ears::Grid::kResolution[static_cast<std::size_t>(level)]);
        EXPECT_EQ(grid.cell(Vec3(-1, 0, 2), level), first);                                   // the low corner
        EXPECT_EQ(grid.cell(Vec3(1, 4, 3), level), first + r * r * r - 1);                    // the high corner
        EXPECT_EQ(grid.cell(Vec3(-50, 99, 2.5), level), grid.cell(Vec3(-1, 4, 2.5), level));  // outside: the nearest
        EXPECT_EQ(grid.cell(Vec3(std::nan(""), 4, 2.5), level), grid.cell(Vec3(-1, 4, 2.5), level));  // NaN x: the first
        first += r * r * r;
    }
    // A finest cell's ancestor at every level is the cell that level gives its points (checked at points
    // all over the box, against the cell computed from the position itself).
    for (int i = 0; i < 2000; ++i) {
        const Vec3 q(-1 + 2 * std::fmod(i * 0.6180339887, 1.0), 4 * std::fmod(i * 0.7548776662, 1.0), 2 + std::fmod(i * 0.5698402910, 1.0));
        const std::size_t finest = grid.cell(q, ears::Grid::kLevels - 1);
        for (int level = 0; level < ears::Grid::kLevels; ++level) ASSERT_EQ(ears::Grid::ancestor(finest, level), grid.cell(q, level)) << i;
    }
    ears::Factors f;
    f.varianceRatio.assign(ears::Grid::cellCount(), -1.0f);
    f.momentRatio.assign(ears::Grid::cellCount(), -1.0f);
    const Vec3 p(0.3, 1.1, 2.7);
    EXPECT_EQ(f.cellAt(grid, p), -1);
    f.momentRatio[grid.cell(p, 1)] = 1;
    EXPECT_EQ(f.cellAt(grid, p), static_cast<long>(grid.cell(p, 1)));
    f.momentRatio[grid.cell(p, 3)] = 1;
    EXPECT_EQ(f.cellAt(grid, p), static_cast<long>(grid.cell(p, 3)));
}

TEST(EarsLearn, RatiosAreTheCellsVarianceAndMomentOverCost) {
    ears::SumTable sums(ears::Learning::sumCount());
    for (int i = 0; i < 40; ++i) sums[0].add(i % 2 ? 3.0 : 1.0, 4);  // mean 2, M = 5, v = 1 x 40/39, cost 4
    for (int i = 0; i < 5; ++i) sums[1].add(1.0, 1);                 // too few to say
    const ears::Factors f = ears::learnFactors(sums, {6.0, 1.5, 1000});
    EXPECT_DOUBLE_EQ(f.scale, std::sqrt(6.0 / 1.5));  // no first-hit cells: the measured sqrt(C / V)
    EXPECT_NEAR(f.momentRatio[0], std::sqrt(5.0 / 4), 1e-6);
    EXPECT_NEAR(f.varianceRatio[0], std::sqrt(40.0 / 39 / 4), 1e-6);
    EXPECT_LT(f.momentRatio[1], 0);
    EXPECT_LT(f.momentRatio[2], 0);
    EXPECT_TRUE(ears::learnFactors(sums, {6.0, 0.0, 1000}).empty());  // an image without variance: nothing to learn
}

// The first hit's factors, solved at once: an epoch of N camera samples whose first hits fall in two
// finest cells with known within-vertex variance v_c, rays per continuation C_c and vertices per sample
// n_c, rendered at q_old = 2 in both; V and C as that epoch measures them from V0 and C0. The learned q_c
// equal the model's optimum sqrt(C0 / V0) sqrt(v_c / C_c) (d(V C)/dq_c = 0 for every cell), whatever q_old
// was, and a brute-force search of V x C finds no lower point.
TEST(EarsLearn, FirstHitFactorsAreTheModelsOptimumInOneEpoch) {
    const ears::Grid grid(Vec3(0, 0, 0), Vec3(1, 1, 1));
    const double N = 1000, v0 = 0.2, c0 = 2;  // optimum q 4.47 and 2.24: neither clamped
    struct Cell {
        Vec3 p;
        double n, v, cost;
    };
    const std::vector<Cell> cells = {{Vec3(0.1, 0.1, 0.1), 0.6, 4.0, 2.0}, {Vec3(0.9, 0.8, 0.7), 0.3, 0.5, 1.0}};
    ears::SumTable sums(ears::Learning::sumCount());
    ears::Learning l(grid);
    double V = v0, C = c0;
    for (const Cell& c : cells) {
        const int vertices = static_cast<int>(c.n * N);
        for (int i = 0; i < vertices; ++i) {
            // Two continuations a vertex, values m +- sqrt(v / 2): sample variance exactly v, rays C_c each.
            const double m = 3 + 0.001 * (i % 7), d = std::sqrt(c.v / 2);
            const auto cell = static_cast<std::uint32_t>(grid.cell(c.p, ears::Grid::kLevels - 1));
            l.add({cell, m - d, static_cast<std::uint64_t>(c.cost), ears::Section::FirstHit});
            l.add({cell, m + d, static_cast<std::uint64_t>(c.cost), ears::Section::FirstHit});
            l.add({cell, c.v, 1, ears::Section::FirstHitVertex});
        }
        V += c.n * c.v / 2;
        C += c.n * 2 * c.cost;
    }
    const ears::Factors f = ears::learnFactors(l.sums(), {C, V, N});
    ASSERT_FALSE(f.empty());
    std::vector<double> q;
    for (const Cell& c : cells) {
        const long cell = ears::Factors::cellAt(f.firstHit, grid, c.p);
        ASSERT_EQ(cell, static_cast<long>(grid.cell(c.p, ears::Grid::kLevels - 1)));
        q.push_back(f.firstHit[static_cast<std::size_t>(cell)]);
        const double exact = std::clamp(std::sqrt(c0 / v0) * std::sqrt(c.v / c.cost), 1.0, ears::kMaxFactor);
        EXPECT_NEAR(q.back(), exact, 1e-5 * exact);
    }
    const auto product = [&](double q1, double q2) {
        return (v0 + cells[0].n * cells[0].v / q1 + cells[1].n * cells[1].v / q2) *
               (c0 + cells[0].n * q1 * cells[0].cost + cells[1].n * q2 * cells[1].cost);
    };
    const double best = product(q[0], q[1]);
    for (double a = 1; a <= ears::kMaxFactor; a += 0.01)
        for (double b = 1; b <= ears::kMaxFactor; b += 0.01) ASSERT_GE(product(a, b), best * (1 - 1e-6)) << a << " " << b;
}

// The continuations of a split vertex (n of them, varying from vertex to vertex): at the first hit, block
// point j of its sample (SampleStream::blockContinuation) at the first-hit estimator's dimensions, as
// PathTracer::splitContinuations reads them; further on, the dimensions of a path of their own. Each direction
// follows the estimator's density, and none repeats another of its pixel (a repeat would show as too many
// directions in a cell).
TEST(EarsSplitDirections, FollowTheEstimatorsDensity) {
    PhongMaterial m;
    m.rhoD = Color(0.3);
    m.rhoS = Color(0.6);
    m.exponent = 30;
    const ShadingContext ctx{sphericalDirection(std::cos(0.7), 0.4), &m, 1, false};
    const auto est = makeEstimator("phong");
    const auto upper = [&](const Vec3& w) { return w.z > 0 ? est->misPdf(ctx, w) : 0.0; };
    test::ChiSquareOptions opts;
    opts.alpha = test::sidakAlpha(2);
    const double mass = test::integrateSphereAdaptive(upper, opts);
    const std::uint32_t spp = 16;
    for (bool firstHit : {true, false}) {
        test::Streams streams(firstHit ? 99 : 100, "sobol", spp);
        std::vector<Vec3> dirs;
        DirectionList out;
        std::size_t calls = 0;
        for (int pixel = 0; pixel < 4000; ++pixel) {
            streams.nextPixel();
            for (std::uint32_t i = 0; i < spp; ++i) {
                const std::uint32_t n = 1 + (pixel + i) % 8;
                for (std::uint32_t j = 0; j < n; ++j, ++calls) {
                    const std::uint64_t path = j == 0 ? 0 : SampleDimensions::splitPath(0, 1, j);
                    SampleStream s = firstHit ? streams.at(i).blockContinuation(j) : streams.at(i);
                    s.setDimension(firstHit ? SampleDimensions::firstHitEstimator(0)
                                            : SampleDimensions::vertex(1, path) + SampleDimensions::kEstimator);
                    out.clear();
                    est->sample(ctx, s, out);
                    for (const auto& d : out) dirs.push_back(d.wi);
                }
            }
        }
        const auto r = test::chiSquareSphere(
            dirs, [&](const Vec3& w) { return upper(w) / mass; }, opts);
        EXPECT_TRUE(r.passed) << (firstHit ? "first hit: " : "further on: ") << r.describe();
        EXPECT_NEAR(static_cast<double>(dirs.size()) / calls, mass, 4 * std::sqrt(mass * (1 - mass) / calls));
    }
}

namespace {

/// First-hit records of `vertices` vertices at p with two continuations each of sample variance v and
/// `cost` rays (as FirstHitFactorsAreTheModelsOptimumInOneEpoch).
void addFirstHits(ears::Learning& l, const Vec3& p, int vertices, double v, std::uint64_t cost) {
    const auto cell = static_cast<std::uint32_t>(l.grid.cell(p, ears::Grid::kLevels - 1));
    for (int i = 0; i < vertices; ++i) {
        const double m = 3 + 0.001 * (i % 7), d = std::sqrt(v / 2);
        l.add({cell, m - d, cost, ears::Section::FirstHit});
        l.add({cell, m + d, cost, ears::Section::FirstHit});
        l.add({cell, v, 1, ears::Section::FirstHitVertex});
    }
}

}  // namespace

// The probe teaches epoch 0 its first-hit factors (the model's, as learnFactors solves them from the same
// sums) and nothing for deeper vertices; at the end of epoch 0 each cell keeps the lesser of the probe's
// factor and epoch 0's, and from then on the first hit's factors hold whatever later epochs measure.
TEST(EarsLearn, AfterTheProbeFirstHitFactorsOnlyFallThenHold) {
    const ears::Grid grid(Vec3(0, 0, 0), Vec3(1, 1, 1));
    const Vec3 a(0.1, 0.1, 0.1), b(0.9, 0.8, 0.7);
    const auto factorAt = [&](const ears::Factors& f, const Vec3& p) {
        const long cell = ears::Factors::cellAt(f.firstHit, grid, p);
        return cell < 0 ? -1.0 : static_cast<double>(f.firstHit[static_cast<std::size_t>(cell)]);
    };
    ears::Learning l(grid);
    addFirstHits(l, a, 600, 4.0, 2);
    addFirstHits(l, b, 300, 0.5, 1);
    l.add({static_cast<std::uint32_t>(grid.cell(a, ears::Grid::kLevels - 1)), 1.0, 3, ears::Section::Deeper});
    ears::SumTable probeSums = l.sums();
    ears::propagateToCoarserCells(probeSums);
    const ears::Factors expected = ears::learnFactors(probeSums, {5.0, 0.4, 1000});
    l.learnFromProbe(0.4, 5000, 1000);
    EXPECT_TRUE(l.probed);
    EXPECT_EQ(l.epoch, 0);
    ASSERT_FALSE(l.factors.empty());
    EXPECT_EQ(factorAt(l.factors, a), factorAt(expected, a));
    EXPECT_EQ(factorAt(l.factors, b), factorAt(expected, b));
    EXPECT_GT(factorAt(l.factors, a), 1.5);
    EXPECT_TRUE(std::all_of(l.factors.momentRatio.begin(), l.factors.momentRatio.end(), [](float r) { return r < 0; }));
    EXPECT_TRUE(std::all_of(l.sums().begin(), l.sums().end(), [](const ears::CellSums& c) { return c.empty(); }));
    const double probeA = factorAt(l.factors, a), probeB = factorAt(l.factors, b);

    // Epoch 0: a's continuations vary less (its own factor falls), b's more (its own would rise).
    addFirstHits(l, a, 600, 0.05, 2);
    addFirstHits(l, b, 300, 16.0, 1);
    ears::SumTable epochSums = l.sums();
    ears::propagateToCoarserCells(epochSums);
    const ears::Factors epoch0 = ears::learnFactors(epochSums, {5.0, 0.4, 1000});
    ASSERT_LT(factorAt(epoch0, a), probeA);
    ASSERT_GT(factorAt(epoch0, b), probeB);
    l.advance(0.4, 5000, 1000);
    EXPECT_EQ(l.epoch, 1);
    EXPECT_EQ(factorAt(l.factors, a), factorAt(epoch0, a));
    EXPECT_EQ(factorAt(l.factors, b), probeB);

    // Epoch 1 measures something else again: the first hit's factors hold.
    addFirstHits(l, a, 600, 8.0, 2);
    addFirstHits(l, b, 300, 0.01, 1);
    const double heldA = factorAt(l.factors, a);
    l.advance(0.4, 10000, 2000);
    EXPECT_EQ(l.epoch, 2);
    EXPECT_EQ(factorAt(l.factors, a), heldA);
    EXPECT_EQ(factorAt(l.factors, b), probeB);
}

// The probe runs once, before the first sample, in renders of at least kProbeMinSpp samples; its samples
// are not the image's (the state counts only the image's camera samples, and its rays add to the render's);
// cancelled part way it learns nothing.
TEST(EarsRender, TheProbeRunsOnceAndStaysOutOfTheImage) {
    const Scene scene = test::makeFurnaceSphere(1.0, 0.5);
    const Accel accel(scene);
    const auto est = makeEstimator("phong");
    for (std::uint32_t spp : {ears::kProbeMinSpp / 2, ears::kProbeMinSpp}) {
        RenderSettings rs = earsSettings(8, 8, spp, 17);
        RenderState state(8, 8, spp);
        renderSamples(scene, accel, *est, rs, state, 2);
        ASSERT_TRUE(state.ears);
        EXPECT_EQ(state.ears->probed, spp >= ears::kProbeMinSpp) << spp;
        EXPECT_EQ(state.samples, 8u * 8u * 2u);
        const std::uint64_t rays = state.rays;
        const bool probed = state.ears->probed;
        probeLearning(scene, accel, *est, rs, state);  // a second call does nothing
        EXPECT_EQ(state.rays, rays);
        renderSamples(scene, accel, *est, rs, state, spp);
        EXPECT_EQ(state.ears->probed, probed);
        EXPECT_EQ(state.samples, 8u * 8u * spp);
    }
    // Cancelled, the probe learns nothing and counts nothing; run again, it probes.
    {
        RenderSettings rs = earsSettings(8, 8, 16, 17);
        RenderState state(8, 8, 16);
        const std::atomic<bool> stop{true};
        rs.cancel = &stop;
        probeLearning(scene, accel, *est, rs, state);
        ASSERT_TRUE(state.ears);
        EXPECT_FALSE(state.ears->probed);
        EXPECT_EQ(state.rays, 0u);
        EXPECT_TRUE(std::all_of(state.ears->sums().begin(), state.ears->sums().end(), [](const ears::CellSums& c) { return c.empty(); }));
        rs.cancel = nullptr;
        probeLearning(scene, accel, *est, rs, state);
        EXPECT_TRUE(state.ears->probed);
        EXPECT_GT(state.rays, 0u);
    }
    // Resumed past its first sample, a render that never probed runs none.
    RenderSettings rs = earsSettings(8, 8, 16, 17);
    RenderState state(8, 8, 16);
    rs.trace.splitting = SplittingMode::None;
    renderSamples(scene, accel, *est, rs, state, 2);
    rs.trace.splitting = SplittingMode::Ears;
    renderSamples(scene, accel, *est, rs, state, 4);
    ASSERT_TRUE(state.ears);
    EXPECT_FALSE(state.ears->probed);
}

// Records are kept while an epoch follows: six samples of a 16-spp render (inside epoch [4, 8), which
// epoch [8, 16) learns from) leave sums; the same six samples of an 8-spp render (the same epoch, now the
// last) leave none, and the image is the same either way (records change no sample).
TEST(EarsRender, OnlyTheLastEpochGoesUnrecorded) {
    const Scene scene = test::makeFurnaceSphere(1.0, 0.5);
    const Accel accel(scene);
    const auto est = makeEstimator("phong");
    std::size_t recorded[2] = {0, 0};
    Image images[2];
    for (int i = 0; i < 2; ++i) {
        const std::uint32_t spp = i == 0 ? 16 : 8;
        RenderSettings rs = earsSettings(8, 8, spp, 91, "independent");
        RenderState state(8, 8, spp);
        renderSamples(scene, accel, *est, rs, state, 6);
        ASSERT_TRUE(state.ears);
        EXPECT_EQ(state.ears->epoch, 2);
        for (const ears::CellSums& c : state.ears->sums()) recorded[i] += c.count;
        images[i] = state.image();
    }
    EXPECT_GT(recorded[0], 8u * 8u * 2u);  // at least one continuation per camera sample of the epoch so far
    EXPECT_EQ(recorded[1], 0u);
    EXPECT_EQ(images[0].pixels, images[1].pixels);
}

// After epoch 0 of a probed render its first-hit factors hold for good (Learning::advance), so nothing
// records the first hit's continuations from epoch 1 on (61% of the diffuse box's records, 84% of sky-n10's):
// inside epoch 0 the FirstHit and FirstHitVertex sections fill, inside epoch 2 only Deeper does. A render too
// short for a probe learns its first hit every epoch and records it in epoch 1 too.
TEST(EarsRender, AfterEpochZeroOfAProbedRenderTheFirstHitGoesUnrecorded) {
    const Scene scene = test::makeFurnaceSphere(1.0, 0.5);
    const Accel accel(scene);
    const auto est = makeEstimator("phong");
    const auto recorded = [](const ears::Learning& l, ears::Section section) {
        std::uint64_t n = 0;
        for (std::size_t c = 0; c < ears::Grid::cellCount(); ++c) n += l.sums()[ears::sectionStart(section) + c].count;
        return n;
    };
    struct Case {
        std::uint32_t spp, upTo;
        int epoch;
        bool firstHit;
    };
    for (const Case k : {Case{16, 1, 0, true}, Case{16, 6, 2, false}, Case{ears::kProbeMinSpp - 1, 3, 1, true}}) {
        RenderSettings rs = earsSettings(8, 8, k.spp, 23);
        RenderState state(8, 8, k.spp);
        renderSamples(scene, accel, *est, rs, state, k.upTo);
        ASSERT_TRUE(state.ears);
        ASSERT_EQ(state.ears->epoch, k.epoch) << k.spp << " spp, " << k.upTo;
        EXPECT_EQ(state.ears->probed, k.spp >= ears::kProbeMinSpp);
        const std::string what = fmt::format("{} spp after {} samples", k.spp, k.upTo);
        // The vertices: every camera sample's first hit inside the closed sphere, after the epoch's first sample.
        const std::uint64_t vertices = recorded(*state.ears, ears::Section::FirstHitVertex);
        EXPECT_EQ(vertices > 0, k.firstHit) << what;
        EXPECT_GE(recorded(*state.ears, ears::Section::FirstHit), vertices) << what;
        EXPECT_EQ(recorded(*state.ears, ears::Section::FirstHit) > 0, k.firstHit) << what;
        if (k.epoch > 0) {
            EXPECT_GT(recorded(*state.ears, ears::Section::Deeper), 0u) << what;
        }
    }
}

// The tracer's two switches of records act apart: the deeper vertices' records (Deeper) and the first hit's
// (FirstHit, FirstHitVertex, BrdfHit). The probe takes the first hit's alone (its deeper factors are never
// kept: Learning::learnFromProbe); an epoch after epoch 0 of a probed render the deeper ones alone. Records
// change no sample: the four settings trace the same radiances bit for bit.
TEST(EarsRender, TheFirstHitsAndTheDeeperVerticesRecordsAreSwitchedApart) {
    const Scene scene = test::makeFurnaceSphere(1.0, 0.5);
    const Accel accel(scene);
    const auto est = makeEstimator("phong");
    const RenderSettings rs = earsSettings(8, 8, 16, 29);
    RenderState state(8, 8, 16);
    const std::unique_ptr<PathTracer> tracer = makeTracer(scene, accel, *est, rs, state);
    const auto sampler = makeSampler("sobol", 16, 29);
    const CameraRays cameraRays(scene.camera, 8, 8);
    std::vector<Color> first;
    for (const auto& [deeper, firstHit] : {std::pair{true, true}, {false, true}, {true, false}, {false, false}}) {
        tracer->setRecords(deeper, firstHit);
        PathScratch scratch;
        TraceStats stats;
        std::vector<Color> radiances;
        for (std::uint32_t i = 0; i < 16; ++i) {
            SampleStream samples(*sampler, 27, i, SampleDimensions::kPixel);
            const Point2 jitter = samples.get2D();
            Vec3 o, d;
            cameraRays(3 + jitter.u, 3 + jitter.v, o, d);
            radiances.push_back(tracer->cameraRadiance(o, d, samples, stats, scratch));
        }
        std::array<std::size_t, ears::kSections> bySection{};
        for (const ears::Record& r : scratch.splitRecords) ++bySection[r.slot / ears::Grid::cellCount()];
        const std::string what = fmt::format("deeper {}, first hit {}", deeper, firstHit);
        EXPECT_EQ(bySection[static_cast<std::size_t>(ears::Section::Deeper)] > 0, deeper) << what;
        EXPECT_EQ(bySection[static_cast<std::size_t>(ears::Section::FirstHit)] > 0, firstHit) << what;
        EXPECT_EQ(bySection[static_cast<std::size_t>(ears::Section::FirstHitVertex)] > 0, firstHit) << what;
        if (first.empty()) first = radiances;
        for (std::size_t i = 0; i < radiances.size(); ++i)
            EXPECT_TRUE(radiances[i].x == first[i].x && radiances[i].y == first[i].y && radiances[i].z == first[i].z)
                << what << ", sample " << i;
    }
}

// Learning is part of a render's cost: the end of an epoch (the image's variance, the sums carried up,
// learnFactors) counts in the state's wall and CPU time, which the study's cost reads. A state whose epoch
// 0 is rendered gains time from endEpochIfDone alone (and one whose epoch is not done gains none).
TEST(EarsRender, TheEndOfAnEpochCountsInTheRendersTime) {
    const Scene scene = makeCornellBox();
    const Accel accel(scene);
    const auto est = makeEstimator("phong");
    const RenderSettings rs = earsSettings(64, 64, 64, 5);
    RenderState state(64, 64, 64);
    renderSegment(scene, accel, *est, rs, state, 1);
    const double seconds = state.seconds, cpu = state.cpuSeconds;
    EXPECT_FALSE(endEpochIfDone(state));  // epoch 0 is samples [0, 2): not done at 1
    EXPECT_EQ(state.seconds, seconds);
    EXPECT_EQ(state.cpuSeconds, cpu);
    renderSegment(scene, accel, *est, rs, state, 2);
    const double wallBefore = state.seconds, cpuBefore = state.cpuSeconds;
    const auto start = std::chrono::steady_clock::now();
    ASSERT_TRUE(endEpochIfDone(state));
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    ASSERT_EQ(state.ears->epoch, 1);
    EXPECT_FALSE(state.ears->factors.empty());
    EXPECT_GT(state.seconds, wallBefore);
    EXPECT_LE(state.seconds - wallBefore, elapsed);  // its own time, nothing else's
    EXPECT_GT(state.cpuSeconds, cpuBefore);
}

// Issue 32's memory bound: the learned structure does not grow with the image (a 4K render holds what a
// 16 x 12 one does, measured in docs/performance.md) and stays under 64 MiB. Its sums alone are the
// table of kSections x Grid::cellCount() CellSums (a lower bound counted apart from bytes()).
TEST(EarsRender, TheStructureIsTheSameSizeAtAnyImageSizeAndUnder64MiB) {
    const Scene scene = makeCornellBox();
    const Accel accel(scene);
    const auto est = makeEstimator("phong");
    std::size_t bytes[2] = {0, 0};
    const int widths[2] = {16, 96}, heights[2] = {12, 72};
    for (int i = 0; i < 2; ++i) {
        const RenderSettings rs = earsSettings(widths[i], heights[i], 16, 3);
        RenderState state(widths[i], heights[i], 16);
        renderSamples(scene, accel, *est, rs, state, 16);
        ASSERT_TRUE(state.ears);
        ASSERT_FALSE(state.ears->factors.empty());  // it learned: both sets of factors hold their buffers
        bytes[i] = state.ears->bytes();
    }
    std::printf("the learned structure: %zu bytes\n", bytes[0]);
    EXPECT_EQ(bytes[0], bytes[1]);
    EXPECT_GE(bytes[0], static_cast<std::size_t>(ears::kSections) * ears::Grid::cellCount() * sizeof(ears::CellSums));
    EXPECT_LE(bytes[0], std::size_t{64} << 20);
}

// The closed furnace (radiance Le / (1 - a) everywhere inside) with EARS's factors at every vertex: the
// mean of 8 repeats within Student's t at the 4-sigma tail, and the render did learn and split. Under the
// independent sampler (EARS's roulette as derived) and under sobol (its roulette floored at plain's).
TEST(EarsRender, TheClosedFurnaceKeepsItsClosedForm) {
    for (const char* sampler : {"independent", "sobol"}) {
        SCOPED_TRACE(sampler);
        const double le = 1.0, albedo = 0.5;
        const Scene scene = test::makeFurnaceSphere(le, albedo);
        const Accel accel(scene);
        const auto est = makeEstimator("phong");
        const double exact = le / (1.0 - albedo) - le * std::pow(albedo, 65) / (1.0 - albedo);  // depth 64 truncation
        std::vector<double> means;
        for (int r = 0; r < 8; ++r) {
            RenderSettings rs = earsSettings(8, 8, 64, mixSeed(77, r), sampler);
            rs.trace.maxDepth = 64;
            RenderState state(8, 8, 64);
            renderSamples(scene, accel, *est, rs, state, 64);
            ASSERT_TRUE(state.ears);
            EXPECT_EQ(state.ears->epoch, 5);  // epochs [0,2) [2,4) ... [32,64): learned five times (not after the last)
            // The last epoch, [32,64), has no epoch after it: its continuations are not recorded.
            for (const ears::CellSums& c : state.ears->sums()) ASSERT_TRUE(c.empty());
            EXPECT_FALSE(state.ears->factors.empty());
            EXPECT_EQ(state.badSamples, 0u);
            const Image img = state.image();
            double sum = 0;
            for (const Color& c : img.pixels) sum += luminance(c);
            means.push_back(sum / static_cast<double>(img.pixels.size()));
        }
        const auto m = test::meanAndError(means);
        EXPECT_LT(std::abs(m.mean - exact) / m.stdError, studentCritical(7)) << m.mean << " against " << exact;
    }
}

// The renderer floors EARS's roulette (ears::flooredRoulette) under a low-discrepancy sampler and not under
// the independent one: a render left to decide equals, bit for bit, the one with the floor forced the way
// its sampler says; and the floor does act on the diffuse box (forced off under sobol, fewer paths live:
// fewer rays for the same camera samples), so that a renderer that stopped setting it would be caught.
TEST(EarsRender, TheRouletteFloorFollowsTheSampler) {
    const Scene scene = loadScene(SYMPHONG_SOURCE_DIR "/scenes/cornell-diffuse.json");
    const Accel accel(scene);
    const auto est = makeEstimator("phong");
    const auto run = [&](const std::string& sampler, std::optional<bool> floor) {
        RenderSettings rs = earsSettings(32, 32, 32, 5, sampler);
        rs.trace.maxDepth = 64;
        rs.earsRouletteFloor = floor;
        return render(scene, accel, *est, rs);
    };
    for (const std::string sampler : {"sobol", "stratified", "independent"}) {
        SCOPED_TRACE(sampler);
        const bool floored = sampler != "independent";
        const RenderResult decided = run(sampler, std::nullopt), same = run(sampler, floored), other = run(sampler, !floored);
        EXPECT_TRUE(sameBits(decided.image, same.image));
        EXPECT_EQ(decided.stats.rays, same.stats.rays);
        const RenderResult& on = floored ? same : other;
        const RenderResult& off = floored ? other : same;
        EXPECT_FALSE(sameBits(on.image, off.image));
        std::printf("%s: %llu rays with the floor, %llu without\n", sampler.c_str(), (unsigned long long)on.stats.rays, (unsigned long long)off.stats.rays);
        EXPECT_GT(static_cast<double>(on.stats.rays), 1.02 * static_cast<double>(off.stats.rays))
            << on.stats.rays << " rays with the floor, " << off.stats.rays << " without";
    }
}

namespace {

/// The study's scenes (scripts/run-studies.sh): the six boxes and the 19 regime scenes.
std::vector<std::string> studyScenes() {
    const std::string dir = SYMPHONG_SOURCE_DIR "/scenes/";
    std::vector<std::string> s = {"cornell",
                                  dir + "cornell-diffuse.json",
                                  dir + "cornell-glossy-100.json",
                                  dir + "cornell-glossy-1000.json",
                                  dir + "cornell-all-glossy.json",
                                  dir + "mcguire-glossy.json"};
    for (const char* light : {"small", "large", "sky", "sun"})
        for (int n : {1, 10, 100, 1000}) s.push_back(dir + "regime/" + light + "-n" + std::to_string(n) + ".json");
    for (const char* name : {"albedo-diffuse", "albedo-specular", "bunny"}) s.push_back(dir + "regime/" + name + ".json");
    return s;
}

/// The image's mean luminance and its standard error (independent sampler: pixels are independent).
std::pair<double, double> meanOf(const Scene& scene, const Accel& accel, SplittingMode splitting, double scale = 1) {
    // Seeds of their own: the two renders independent, as the z below assumes.
    RenderSettings rs = earsSettings(40, 30, 128, 2024 + static_cast<std::uint64_t>(splitting), "independent");
    rs.trace.splitting = splitting;
    const auto est = makeEstimator("phong");
    const auto [m, se] = test::imageMeanAndError(render(scene, accel, *est, rs));
    return {scale * m, scale * se};
}

}  // namespace

// Unbiased on every scene of the study: the mean image with EARS against phong's (both 40x30 at 128 spp
// under the independent sampler, independent seeds, their own standard errors), |z| < 4; and the
// comparison can fail: the
// box 10% brighter is caught (the smallest bias it catches is printed per scene: 0.3% to 6%, heavy-tailed
// scenes the most).
TEST(EarsRender, MeanImageAgreesWithPhongOnEveryStudyScene) {
    for (const std::string& name : studyScenes()) {
        const Scene scene = loadScene(name);
        const Accel accel(scene);
        const auto [mp, sp] = meanOf(scene, accel, SplittingMode::None);
        const auto [me, se] = meanOf(scene, accel, SplittingMode::Ears);
        const double z = (me - mp) / std::sqrt(sp * sp + se * se);
        std::printf("%-28s phong %.5f +- %.5f  ears %.5f +- %.5f  z %+.2f  (catches %.1f%%)\n",
                    std::filesystem::path(name).filename().c_str(), mp, sp, me, se, z, 400 * std::sqrt(sp * sp + se * se) / mp);
        EXPECT_LT(std::abs(z), 4.0) << name;
        if (name == "cornell") {
            const auto [mb, sb] = meanOf(scene, accel, SplittingMode::Ears, 1.10);
            EXPECT_GT(std::abs(mb - mp) / std::sqrt(sp * sp + sb * sb), 4.0) << "a 10% bias must be caught";
        }
    }
}

// --splitting ears-orbit (a first hit's 2, 4 or 8 continuations one symmetric orbit): unbiased on the scenes of
// scripts/ears-study.sh, whose first hits split (the mean image against phong's, |z| < 4, as above; each copy
// of an orbit has phong's density: SymmetricMix tests its chi-square copy by copy).
TEST(EarsOrbitRender, MeanImageAgreesWithPhong) {
    const std::string dir = SYMPHONG_SOURCE_DIR "/scenes/";
    for (const std::string& name : {std::string("cornell"), dir + "cornell-glossy-100.json", dir + "regime/sky-n10.json",
                                   dir + "regime/small-n10.json", dir + "regime/large-n100.json", dir + "regime/albedo-diffuse.json"}) {
        const Scene scene = loadScene(name);
        const Accel accel(scene);
        const auto [mp, sp] = meanOf(scene, accel, SplittingMode::None);
        const auto [mo, so] = meanOf(scene, accel, SplittingMode::EarsOrbit);
        const double z = (mo - mp) / std::sqrt(sp * sp + so * so);
        std::printf("%-28s phong %.5f +- %.5f  ears-orbit %.5f +- %.5f  z %+.2f\n", std::filesystem::path(name).filename().c_str(), mp, sp,
                    mo, so, z);
        EXPECT_LT(std::abs(z), 4.0) << name;
    }
}

// ears-orbit is deterministic at any thread count, and its orbits are used: on sky-n10 (first hits split 8
// ways) the image differs from ears's with the same seed.
TEST(EarsOrbitRender, SameImageAtAnyThreadCountAndNotEarssImage) {
    const Scene scene = loadScene(SYMPHONG_SOURCE_DIR "/scenes/regime/sky-n10.json");
    const Accel accel(scene);
    const auto est = makeEstimator("phong");
    const auto run = [&](int threads, SplittingMode mode) {
        RenderSettings rs = earsSettings(40, 24, 16, 5);
        rs.trace.splitting = mode;
        rs.threads = threads;
        RenderState state(40, 24, 16);
        renderSamples(scene, accel, *est, rs, state, 16);
        return state;
    };
    const RenderState one = run(1, SplittingMode::EarsOrbit), two = run(2, SplittingMode::EarsOrbit);
    EXPECT_TRUE(sameBits(one.image(), two.image()));
    EXPECT_EQ(one.rays, two.rays);
    EXPECT_GT(one.paths, one.samples);  // it split
    EXPECT_FALSE(sameBits(one.image(), run(1, SplittingMode::Ears).image()));
}

// The same image, variance and learned factors at 1, 2 and 5 threads and in passes of 3, 7 and 16 samples
// as in one pass; a different seed changes the image.
TEST(EarsRender, SameImageAtAnyThreadCountAndAnyPasses) {
    const Scene scene = loadScene(SYMPHONG_SOURCE_DIR "/scenes/regime/sky-n10.json");
    const Accel accel(scene);
    const auto est = makeEstimator("phong");
    const auto run = [&](int threads, const std::vector<std::uint32_t>& passes, std::uint64_t seed) {
        RenderSettings rs = earsSettings(40, 24, 16, seed);
        rs.threads = threads;
        RenderState state(40, 24, 16);
        for (std::uint32_t upTo : passes) renderSamples(scene, accel, *est, rs, state, upTo);
        return state;
    };
    const RenderState one = run(1, {16}, 5);
    EXPECT_GT(one.paths, one.samples);  // it split somewhere
    for (const auto& [threads, passes] : std::vector<std::pair<int, std::vector<std::uint32_t>>>{{2, {16}}, {5, {16}}, {2, {3, 7, 16}}}) {
        const RenderState other = run(threads, passes, 5);
        EXPECT_TRUE(sameBits(one.image(), other.image())) << threads << " threads, " << passes.size() << " passes";
        EXPECT_TRUE(sameBits(one.variance(), other.variance())) << threads << " threads";
        EXPECT_EQ(one.rays, other.rays);
        ASSERT_TRUE(other.ears);
        EXPECT_EQ(one.ears->factors.momentRatio, other.ears->factors.momentRatio);
        EXPECT_EQ(one.ears->factors.scale, other.ears->factors.scale);
    }
    EXPECT_FALSE(sameBits(one.image(), run(2, {16}, 6).image()));
}

// A checkpoint taken inside an epoch (9 of 16 samples: the factors of epoch 3 learned from epoch 2's 4
// samples, epoch 3's sums begun) reads back every learned ratio and sum exactly and resumes to the
// uninterrupted image bit for bit. The image is large enough (32 x 32) that cells have learned factors by
// then: at 24 x 16 and 5 samples none had its kMinRecords continuations, and a checkpoint that lost or
// mixed up the factors resumed to the same image.
TEST(EarsCheckpoint, ResumesInsideAnEpochBitForBit) {
    const Scene scene = loadScene(SYMPHONG_SOURCE_DIR "/scenes/regime/sky-n100.json");
    const Accel accel(scene);
    const auto est = makeEstimator("phong");
    const RenderSettings rs = earsSettings(32, 32, 16, 3);
    RenderState whole(32, 32, 16);
    renderSamples(scene, accel, *est, rs, whole, 16);
    RenderState part(32, 32, 16);
    renderSamples(scene, accel, *est, rs, part, 9);
    ASSERT_EQ(part.ears->epoch, 3);
    const std::vector<float>& moment = part.ears->factors.momentRatio;
    const long learned = std::count_if(moment.begin(), moment.end(), [](float r) { return r >= 0; });
    EXPECT_GT(learned, 10) << "cells with learned factors at the checkpoint";
    const test::TempDir tmp;
    const std::string path = tmp.file("ears.ckpt");
    const RenderIdentity id{"sky-n100", "0", nlohmann::json::object()};
    writeCheckpoint(path, id, part);
    RenderIdentity readId;
    RenderState resumed;
    readCheckpoint(path, readId, resumed);
    ASSERT_TRUE(resumed.ears);
    EXPECT_EQ(resumed.ears->epoch, 3);
    EXPECT_EQ(resumed.ears->factors.momentRatio, part.ears->factors.momentRatio);
    EXPECT_EQ(resumed.ears->factors.varianceRatio, part.ears->factors.varianceRatio);
    EXPECT_EQ(resumed.ears->factors.scale, part.ears->factors.scale);
    EXPECT_EQ(resumed.ears->factors.firstHit, part.ears->factors.firstHit);
    EXPECT_EQ(resumed.ears->factors.misShare, part.ears->factors.misShare);
    EXPECT_EQ(std::memcmp(resumed.ears->sums().data(), part.ears->sums().data(), part.ears->sums().size() * sizeof(ears::CellSums)), 0);
    renderSamples(scene, accel, *est, rs, resumed, 16);
    EXPECT_TRUE(sameBits(whole.image(), resumed.image()));
    EXPECT_TRUE(sameBits(whole.variance(), resumed.variance()));
}

// The default, --splitting auto, renders what --splitting ears renders from kAutoSplittingMinSpp samples on, and
// what --splitting none renders where --split, --joint-first-bounce or fewer samples rule it out; the summary
// line names the one used, and the scene file's own settings count as the user's.
TEST(EarsCli, TheDefaultSplittingIsEarsWhereItCanLearn) {
    const test::TempDir tmp;
    const std::vector<std::string> base{"render", "cornell", "-W", "24", "-H", "18", "--seed", "4", "-t", "2"};
    const auto render = [&](const std::string& name, std::vector<std::string> extra) {
        std::vector<std::string> args = base;
        args.insert(args.end(), extra.begin(), extra.end());
        args.insert(args.end(), {"-o", tmp.file(name + ".exr")});
        const test::CliRun r = test::runCliArgs(args);
        EXPECT_EQ(r.code, 0) << name << ": " << r.err;
        return std::make_pair(readExr(tmp.file(name + ".exr")), r.out);
    };
    const std::string spp = std::to_string(kAutoSplittingMinSpp), fewer = std::to_string(kAutoSplittingMinSpp - 1);
    const auto [autoImage, autoOut] = render("auto", {"--spp", spp});
    const auto [earsImage, earsOut] = render("ears", {"--spp", spp, "--splitting", "ears"});
    const auto [noneImage, noneOut] = render("none", {"--spp", spp, "--splitting", "none"});
    EXPECT_TRUE(sameBits(autoImage, earsImage));
    EXPECT_FALSE(sameBits(autoImage, noneImage));
    EXPECT_NE(autoOut.find("splitting ears:"), std::string::npos) << autoOut;
    EXPECT_NE(noneOut.find("splitting none:"), std::string::npos) << noneOut;
    const auto [splitAuto, splitOut] = render("split-auto", {"--spp", spp, "--split", "2"});
    const auto [splitNone, unused1] = render("split-none", {"--spp", spp, "--split", "2", "--splitting", "none"});
    EXPECT_TRUE(sameBits(splitAuto, splitNone));
    EXPECT_NE(splitOut.find("splitting none:"), std::string::npos) << splitOut;
    const auto [fewAuto, fewOut] = render("few-auto", {"--spp", fewer});
    const auto [fewNone, unused2] = render("few-none", {"--spp", fewer, "--splitting", "none"});
    EXPECT_TRUE(sameBits(fewAuto, fewNone));
    const std::string scene = tmp.write("s.json", R"({"builtin": "cornell", "render": {"spp": 64, "split": 2}})");
    const test::CliRun r =
        test::runCliArgs({"render", scene, "-W", "24", "-H", "18", "--seed", "4", "-t", "2", "-o", tmp.file("scene.exr")});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_TRUE(sameBits(readExr(tmp.file("scene.exr")), splitNone)) << "the scene's --split 2 rules ears out as the user's would";
}

TEST(EarsCli, BadValuesAreRefusedWithExitCode2) {
    const test::TempDir tmp;
    auto r = test::runCliArgs({"render", "--splitting", "foo", "-o", tmp.file("a.png")});
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_NE(r.err.find("--splitting: foo not in {auto,none,ears,ears-orbit}"), std::string::npos) << r.err;
    r = test::runCliArgs({"render", "--splitting", "ears", "--split", "2", "-o", tmp.file("b.png")});
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_NE(r.err.find("--split 2 and --splitting ears"), std::string::npos) << r.err;
    const std::string scene = tmp.write("s.json", R"({"builtin": "cornell", "render": {"splitting": "sometimes"}})");
    r = test::runCliArgs({"render", scene, "-o", tmp.file("c.png")});
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_NE(r.err.find("s.json"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("sometimes"), std::string::npos) << r.err;
    // ears-orbit's copies have phong's density: another estimator is refused, naming it.
    r = test::runCliArgs({"render", "--splitting", "ears-orbit", "-e", "cosine", "-o", tmp.file("d.png")});
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_NE(r.err.find("ears-orbit needs --estimator phong (got 'cosine')"), std::string::npos) << r.err;
    EXPECT_FALSE(std::filesystem::exists(tmp.file("a.png")) || std::filesystem::exists(tmp.file("b.png")) ||
                 std::filesystem::exists(tmp.file("c.png")) || std::filesystem::exists(tmp.file("d.png")));
    // The study's reference takes the same names, and ears-orbit there needs a phong reference too.
    r = test::runCliArgs({"study", "--reference-splitting", "foo", "--out", tmp.file("study1")});
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_NE(r.err.find("--reference-splitting: foo not in {none,ears,ears-orbit}"), std::string::npos) << r.err;
    r = test::runCliArgs({"study", "--reference-splitting", "ears-orbit", "--reference-estimator", "cosine", "--out", tmp.file("study2")});
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_NE(r.err.find("--reference-splitting ears-orbit: needs --reference-estimator phong"), std::string::npos) << r.err;
    EXPECT_FALSE(std::filesystem::exists(tmp.file("study1")) || std::filesystem::exists(tmp.file("study2")));
}
