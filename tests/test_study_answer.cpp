// study/answer.cpp: the factors of the answer's "Most efficient" lines, on rows made by hand whose MSE and
// relMSE rank the variants differently, against the ratios computed again here from the rows by the
// definition (answer_factors.h). TinyStudy.AnswerFactorsAreTheRatiosOfResultsCsv (test_study.cpp) does the
// same from a real study's results.csv.
#include "answer_factors.h"

#include "study/answer.h"

#include <gtest/gtest.h>

#include <map>
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

}  // namespace
}  // namespace symphong
