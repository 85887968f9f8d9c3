// study/answer.h — the study's answer and tables, computed from its rows: which variant is most efficient
// and by how much, whether the symmetric variants pay (each fair pair: equal paths per camera sample,
// study/comparisons.h), what ended the repeats, each factor with its 95% interval over the paired repeats
// (study/intervals.h), and one compact table per measure (rows: variants, columns: spp).
// report.md (report.cpp) and report.html (report_html.cpp) show the same lines and tables, and
// results.json carries the comparisons (answerComparisonsJson) for scripts/study-report.py.
#pragma once

#include "study/comparisons.h"
#include "study/intervals.h"
#include "study/study.h"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace symphong {

/// The median of the values (the mean of the middle two for an even count), by partial ordering.
double median(std::vector<double> v);

struct ReportCell {
    std::string text;
    std::optional<double> value;  ///< what the cell sorts by; none for "-" and names
};

struct ReportTable {
    std::string title, note;
    std::vector<std::string> columns;
    std::vector<std::vector<ReportCell>> rows;
};

/// What the answer says of how the repeats ended.
struct RepeatsNote {
    std::string stoppedBy = "fixed";  ///< StudyOutcome::stoppedBy
    double targetInterval = 0;
};

/// The answer: at most ten lines of Markdown (each a bullet's text, without "- ").
std::vector<std::string> studyAnswer(const StudyConfig& c, const std::vector<StudyRow>& rows, const std::vector<StudySummary>& summary,
                                     const RepeatsNote& repeats = {});

/// Every comparison of the answer at the top spp, with its ratio, interval, verdict and repeats, by MSE
/// and by relMSE (results.json's "comparisons").
nlohmann::json answerComparisonsJson(const StudyConfig& c, const std::vector<StudyRow>& rows, const std::vector<StudySummary>& summary);

/// The tables: efficiency by MSE and by relMSE relative to the yardstick under the same sampler, the RMSE,
/// each variant x spp with its interval, and the repeats and costs at the top spp.
std::vector<ReportTable> studyTables(const StudyConfig& c, const std::vector<StudyRow>& rows, const std::vector<StudySummary>& summary);

/// A table as Markdown (its title as a level-2 heading, its note, then the table).
std::string tableMarkdown(const ReportTable& t);

/// "CPU time", "wall time", "rays": what efficiency divides by, in words.
std::string costWords(StudyCost cost);

}  // namespace symphong
