// study/answer.h — the study's answer and tables, computed from its rows: which variant is most efficient
// and by how much, whether the symmetric variants pay, each factor with its 95% interval from the repeats
// (a bootstrap of the ratio of medians), and one compact table per measure (rows: variants, columns: spp).
// report.md (report.cpp) and report.html (report_html.cpp) show the same lines and tables.
#pragma once

#include "study/study.h"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace symphong {

/// The median of the values (the mean of the middle two for an even count), by partial ordering: the
/// study's summary takes it over repeats and the bootstrap thousands of times.
double median(std::vector<double> v);

/// A ratio of two medians with its 95% percentile-bootstrap interval.
struct RatioInterval {
    double point = 0, lo = 0, hi = 0;
};

/// median(a) / median(b) and the 2.5 and 97.5 percentiles of the same ratio over `draws` resamplings of a
/// and of b, each drawn with replacement from its own values (a fixed `seed`: the same interval every
/// time). Empty input or a median of b that is not > 0: nothing. No interval (lo = hi = the point) with
/// one value on each side or no draws.
std::optional<RatioInterval> bootstrapRatio(const std::vector<double>& a, const std::vector<double>& b, std::uint64_t seed,
                                            int draws = 4000);

/// "1.2x [0.95, 1.5]".
std::string intervalText(const RatioInterval& r);

struct ReportCell {
    std::string text;
    std::optional<double> value;  ///< what the cell sorts by; none for "-" and names
};

struct ReportTable {
    std::string title, note;
    std::vector<std::string> columns;
    std::vector<std::vector<ReportCell>> rows;
};

/// The bootstrap's resamplings per interval in the report; an interrupted study's report has none (its
/// intervals took seconds under a sanitizer, more than a job stopped by its launcher has).
inline constexpr int kReportDraws = 4000;

/// The answer: at most ten lines of Markdown (each a bullet's text, without "- ").
std::vector<std::string> studyAnswer(const StudyConfig& c, const std::vector<StudyRow>& rows, const std::vector<StudySummary>& summary,
                                     int draws = kReportDraws);

/// The tables: efficiency by MSE and by relMSE relative to the yardstick under the same sampler, and the
/// RMSE, each variant x spp with its interval.
std::vector<ReportTable> studyTables(const StudyConfig& c, const std::vector<StudyRow>& rows, const std::vector<StudySummary>& summary,
                                     int draws = kReportDraws);

/// A table as Markdown (its title as a level-2 heading, its note, then the table).
std::string tableMarkdown(const ReportTable& t);

}  // namespace symphong
