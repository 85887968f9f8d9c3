// study/answer.cpp: the factors of the answer's "Most efficient" lines, on rows made by hand whose MSE and
// relMSE rank the variants differently, against the ratios computed again here from the rows by the
// definition (answer_factors.h). TinyStudy.AnswerFactorsAreTheRatiosOfResultsCsv (test_study.cpp) does the
// same from a real study's results.csv.
#include "answer_factors.h"

#include "study/answer.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <regex>
#include <string>
#include <vector>

namespace symphong {
namespace {

// Three repeats of three unbiased variants at 16 spp, numbers chosen so that every factor differs by
// measure: by MSE (efficiency 1/(E[MSE] E[cost])) phong 0.5, cosine 0.417, uniform 0.2: phong first, 1.2x
// cosine; by relMSE uniform 1, cosine 0.278, phong 0.25: uniform first, 3.6x cosine and 4.0x the yardstick
// phong. A factor taken from the other measure (or the other variant) is off by far more than its digits.
TEST(StudyAnswer, MostEfficientLinesQuoteTheRatiosOfTheirOwnMeasure) {
    StudyConfig c;
    c.estimators = {"uniform", "cosine", "phong"};
    c.spps = {16};
    c.repeats = 3;
    struct Numbers {
        double mse[3], relMse[3], cost[3];
    };
    const std::map<std::string, Numbers> numbers = {
        {"uniform", {{4, 5, 6}, {1, 1.1, 0.9}, {1, 1, 1}}},
        {"cosine", {{2, 2.5, 1.5}, {3, 3.3, 2.7}, {1.1, 1.2, 1.3}}},
        {"phong", {{1, 1.2, 0.8}, {2, 2.2, 1.8}, {1.9, 2.1, 2.0}}},
    };
    std::vector<StudyRow> rows;
    std::map<std::string, std::vector<answer_factors::Sample>> byMse, byRel;
    for (const StudyVariant& v : studyVariants(c))
        for (int i = 0; i < 3; ++i) {
            const Numbers& n = numbers.at(v.label);
            StudyRow r;
            r.estimator = v.estimator, r.variant = v.label, r.sampler = v.sampler, r.mode = "branch";
            r.spp = 16, r.repeat = i, r.width = r.height = 8;
            r.mse = n.mse[i], r.relMse = n.relMse[i], r.cost = r.cpuSeconds = r.seconds = n.cost[i];
            r.rmse = std::sqrt(r.mse);
            r.efficiency = 1 / (r.mse * r.cost), r.efficiencyRel = 1 / (r.relMse * r.cost);
            rows.push_back(r);
            byMse[v.label].push_back({i, n.mse[i], n.cost[i]});
            byRel[v.label].push_back({i, n.relMse[i], n.cost[i]});
        }
    ASSERT_EQ(rows.size(), 9u) << "the variants' labels are the estimators' names";
    const std::vector<std::string> answer = studyAnswer(c, rows, summarizeStudy(rows));
    std::map<std::string, answer_factors::Line> lines;
    for (const std::string& text : answer)
        if (const auto line = answer_factors::parseMostEfficient(text)) lines[text.find("by relMSE") != std::string::npos ? "relMSE" : "MSE"] = *line;
    ASSERT_EQ(lines.size(), 2u) << ::testing::PrintToString(answer);
    // The ranking and the quoted variants, by hand from the efficiencies above.
    EXPECT_EQ(lines["MSE"].best, "phong");
    ASSERT_EQ(lines["MSE"].factors.size(), 1u) << "the yardstick is first: no third variant quoted";
    EXPECT_EQ(lines["MSE"].factors[0].against, "cosine");
    EXPECT_EQ(lines["relMSE"].best, "uniform");
    ASSERT_EQ(lines["relMSE"].factors.size(), 2u);
    EXPECT_EQ(lines["relMSE"].factors[0].against, "cosine");
    EXPECT_EQ(lines["relMSE"].factors[1].against, "phong");
    for (auto& [measure, line] : lines) {
        const auto& samples = measure == "MSE" ? byMse : byRel;
        for (const answer_factors::Quoted& q : line.factors)
            answer_factors::expectQuotes(q, answer_factors::ratio(samples.at(line.best), samples.at(q.against)),
                                         measure + ": `" + line.best + "` against `" + q.against + "`");
    }
    // The point factors by hand: (E[MSE] E[cost]) of the next over the best's: 2 x 1.2 / (1 x 2) = 1.2; by relMSE
    // 3 x 1.2 / (1 x 1) = 3.6 and 2 x 2 / (1 x 1) = 4.0.
    EXPECT_NEAR(lines["MSE"].factors[0].point, (2.0 * 1.2) / (1.0 * 2.0), 0.05);
    EXPECT_NEAR(lines["relMSE"].factors[0].point, 3.6, 0.05);
    EXPECT_NEAR(lines["relMSE"].factors[1].point, 4.0, 0.05);
}

// study/answer.cpp earsLine: a study with --splittings none,ears,ears-orbit says in one line whether learning
// pays: each learned variant against plain `phong`, and the orbit against independent directions, with the
// factors computed again here by the definition (answer_factors.h). By hand (cost-weighted MSE): ears 0.48
// against phong's 1: 2.1x, ahead; the orbit 0.75: 1.3x phong, ahead, and 0.64x ears, behind. Both learned
// variants ahead of plain tracing: "Yes". A study without them has no such line.
TEST(StudyAnswer, EarsLineQuotesEachLearnedVariantAndTheOrbitAgainstIndependentDirections) {
    StudyConfig c;
    c.estimators = {"phong"};
    c.splittings = {"none", "ears", "ears-orbit"};
    c.splitEstimators = {"phong"};
    c.spps = {16};
    c.repeats = 3;
    struct Numbers {
        double mse[3], cost[3];
    };
    const std::map<std::string, Numbers> numbers = {
        {"phong", {{1, 1.1, 0.9}, {1, 1.02, 0.98}}},
        {"phong+ears", {{0.4, 0.42, 0.38}, {1.2, 1.21, 1.19}}},
        {"phong+ears-orbit", {{0.6, 0.63, 0.58}, {1.25, 1.24, 1.26}}},
    };
    std::vector<StudyRow> rows;
    std::map<std::string, std::vector<answer_factors::Sample>> samples;
    for (const StudyVariant& v : studyVariants(c)) {
        ASSERT_TRUE(numbers.count(v.label)) << "unexpected variant " << v.label;
        for (int i = 0; i < 3; ++i) {
            const Numbers& n = numbers.at(v.label);
            StudyRow r;
            r.estimator = v.estimator, r.variant = v.label, r.sampler = v.sampler, r.mode = "branch";
            r.spp = 16, r.repeat = i, r.width = r.height = 8;
            r.mse = r.relMse = n.mse[i], r.cost = r.cpuSeconds = r.seconds = n.cost[i];
            r.rmse = std::sqrt(r.mse);
            r.efficiency = r.efficiencyRel = 1 / (r.mse * r.cost);
            rows.push_back(r);
            samples[v.label].push_back({i, n.mse[i], n.cost[i]});
        }
    }
    ASSERT_EQ(samples.size(), 3u);
    const std::vector<std::string> answer = studyAnswer(c, rows, summarizeStudy(rows));
    const auto line = std::find_if(answer.begin(), answer.end(),
                                   [](const std::string& l) { return l.rfind("**Does efficiency-aware splitting pay?**", 0) == 0; });
    ASSERT_NE(line, answer.end()) << ::testing::PrintToString(answer);
    EXPECT_EQ(line->rfind("**Does efficiency-aware splitting pay?** Yes: ", 0), 0u) << *line;
    static const std::regex part(R"(`([^`]+)` against `([^`]+)` \*\*([a-z ]+)\*\*, ([0-9.]+)x \[([0-9.]+), ([0-9.]+)\])");
    std::map<std::pair<std::string, std::string>, std::pair<std::string, answer_factors::Quoted>> quoted;
    for (std::sregex_iterator it(line->begin(), line->end(), part), end; it != end; ++it)
        quoted[{(*it)[1], (*it)[2]}] = {(*it)[3], {(*it)[2], std::stod((*it)[4]), std::stod((*it)[5]), std::stod((*it)[6])}};
    const std::map<std::pair<std::string, std::string>, std::string> expected = {
        {{"phong+ears", "phong"}, "ahead"}, {{"phong+ears-orbit", "phong"}, "ahead"}, {{"phong+ears-orbit", "phong+ears"}, "behind"}};
    ASSERT_EQ(quoted.size(), expected.size()) << *line;
    for (const auto& [pair, verdict] : expected) {
        ASSERT_TRUE(quoted.count(pair)) << pair.first << " against " << pair.second << " missing: " << *line;
        EXPECT_EQ(quoted[pair].first, verdict) << *line;
        answer_factors::expectQuotes(quoted[pair].second, answer_factors::ratio(samples.at(pair.first), samples.at(pair.second)),
                                     pair.first + " against " + pair.second);
    }
    const double earsPoint = quoted[{"phong+ears", "phong"}].second.point, orbitPoint = quoted[{"phong+ears-orbit", "phong+ears"}].second.point;
    EXPECT_NEAR(earsPoint, 1.0 / (0.4 * 1.2), 0.1);
    EXPECT_NEAR(orbitPoint, (0.4 * 1.2) / (0.6033 * 1.25), 0.02);

    c.splittings = {"none"};
    std::vector<StudyRow> plain;
    for (const StudyRow& r : rows)
        if (r.variant == "phong") plain.push_back(r);
    for (const std::string& l : studyAnswer(c, plain, summarizeStudy(plain)))
        EXPECT_EQ(l.find("efficiency-aware"), std::string::npos) << l;
}

// A study stopped by its target when repeats could narrow nothing more, while the reference's own error leaves a
// comparison wider than the target: the repeats line says which, and what to do. cosine has half phong's MSE in
// every repeat (the repeats' interval has no width), and a reference error of sd 0.1 in every row widens it to
// +-18% on the log scale (1.96 x 0.1 x |1/0.5 - 1/1|); without that error the line ends at the target.
TEST(StudyAnswer, RepeatsLineNamesTheComparisonsThatTheReferenceLeavesWide) {
    StudyConfig c;
    c.estimators = {"cosine", "phong"};
    c.spps = {16};
    c.repeats = 3;
    for (const double sd : {0.0, 0.1}) {
        std::vector<StudyRow> rows;
        for (const StudyVariant& v : studyVariants(c))
            for (int i = 0; i < 3; ++i) {
                StudyRow r;
                r.estimator = v.estimator, r.variant = v.label, r.sampler = v.sampler, r.mode = "branch";
                r.spp = 16, r.repeat = i, r.width = r.height = 8;
                r.mse = r.relMse = v.label == "cosine" ? 0.5 : 1.0;
                r.cost = r.cpuSeconds = r.seconds = 1.0;
                r.rmse = std::sqrt(r.mse), r.efficiency = r.efficiencyRel = 1 / r.mse;
                r.referenceSd = sd;
                rows.push_back(r);
            }
        const std::vector<std::string> answer = studyAnswer(c, rows, summarizeStudy(rows), RepeatsNote{"target", 0.1});
        const auto line =
            std::find_if(answer.begin(), answer.end(), [](const std::string& l) { return l.find("Repeats:") != std::string::npos; });
        ASSERT_NE(line, answer.end()) << ::testing::PrintToString(answer);
        EXPECT_NE(line->find("stopped when every comparison was decided within +-10%"), std::string::npos) << *line;
        const std::string wide = " by its repeats; the reference's own error leaves `cosine` against `phong` wider (raise --reference-spp)";
        EXPECT_EQ(line->find(wide) != std::string::npos, sd > 0) << *line;
    }
}

}  // namespace
}  // namespace symphong
