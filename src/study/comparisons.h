// study/comparisons.h — what the study's answer compares, and when it has repeated enough to say it.
// Each variant is compared with the yardstick (`phong`) under the same sampler; each symmetric candidate
// that starts a known number K of paths per camera sample is also compared with the yardstick split K
// ways at the first hit (`phong+splitK`): a fair pair, equal paths per camera sample (K = 1: the spread
// mode against plain `phong`). A comparison is the efficiency ratio of study/intervals.h over the
// repeats both variants have (paired by repeat number: the same seed), and with --target-interval the
// study renders more repeats of the variants whose comparisons are not yet settled (variantsToRepeat).
#pragma once

#include "study/intervals.h"
#include "study/study.h"

#include <optional>
#include <set>
#include <string>
#include <vector>

namespace symphong {

/// `variant` against `against`.
struct VariantPair {
    std::string variant, against;
    bool fairPair = false;  ///< equal paths per camera sample: the answer gives it a line of its own
    int paths = 0;          ///< fair pairs: the paths per camera sample of both
};

/// The answer's comparisons among `variants`, in their order: each against the yardstick under the same
/// sampler (the yardstick itself not), then the fair pairs of candidates with more than one path per camera
/// sample; a candidate with one path per camera sample has its comparison with the yardstick marked fair;
/// an ears-orbit variant against its ears variant.
std::vector<VariantPair> studyComparisons(const std::vector<StudyVariant>& variants);

/// Which measure of the rows a ratio uses: 1/(MSE x cost) or 1/(relMSE x cost).
enum class ErrorMeasure { Mse, RelMse };

/// Whether a ratio's interval by MSE includes the reference's own error that the rows carry
/// (StudyRow::referenceSd): the answer's intervals do; the rule that adds repeats judges the repeats' part
/// alone, the one that more repeats can narrow.
enum class ReferenceError { Included, Left };

/// The efficiency ratio of `variant` over `against` at `spp` from the repeats both have (by repeat number).
std::optional<RatioInterval> compareVariants(const std::vector<StudyRow>& rows, const std::string& variant, const std::string& against,
                                             std::uint32_t spp, ErrorMeasure measure = ErrorMeasure::Mse,
                                             ReferenceError reference = ReferenceError::Included);

/// Whether the variant's rows at spp are flagged significantly biased (its efficiency then means little:
/// its comparisons are not waited for).
bool biasedAt(const std::vector<StudyRow>& rows, const std::string& variant, std::uint32_t spp);

/// The variants that need another repeat at spp for every comparison to be settled (study/intervals.h:
/// ahead, behind or equal, relative half-width at most `target`) as far as repeats can settle it (the
/// interval without the reference's own error, which no repeat narrows): both sides of each unsettled
/// comparison whose variants are not biased. Empty: every comparison is settled so.
std::set<std::string> variantsToRepeat(const std::vector<StudyRow>& rows, std::uint32_t spp, const std::vector<VariantPair>& comparisons,
                                       double target);

/// The repeats of `variant` at spp.
int repeatsOf(const std::vector<StudyRow>& rows, const std::string& variant, std::uint32_t spp);

}  // namespace symphong
