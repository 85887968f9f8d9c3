#include "study/comparisons.h"

#include "estimators/registry.h"

#include <algorithm>
#include <map>

namespace symphong {

namespace {

/// The yardstick variant that `v` is compared with: the yardstick estimator, unsplit unless `split` says,
/// under v's sampler (the first one when v has a sampler of its own).
const StudyVariant* yardstickFor(const std::vector<StudyVariant>& variants, const StudyVariant& v, int split) {
    const std::string_view yard = yardstickEstimator();
    const EstimatorEntry* own = findEstimator(v.estimator);
    const bool ownSampler = own && !own->traits.ownSampler.empty();
    const StudyVariant* found = nullptr;
    for (const StudyVariant& y : variants)
        if (y.estimator == yard && y.split == split && y.mode == SymmetricMode::Branch && y.splitting == SplittingMode::None &&
            (y.sampler == v.sampler || ownSampler)) {
            if (y.sampler == v.sampler) return &y;
            if (!found) found = &y;
        }
    return found;
}

bool isCandidate(const StudyVariant& v) {
    const EstimatorEntry* e = findEstimator(v.estimator);
    return e && e->traits.role == EstimatorRole::Candidate && e->traits.hasDensity;
}

}  // namespace

std::vector<VariantPair> studyComparisons(const std::vector<StudyVariant>& variants) {
    std::vector<VariantPair> out, pairs;
    for (const StudyVariant& v : variants) {
        const StudyVariant* y = yardstickFor(variants, v, 1);
        if (y && y != &v) out.push_back({v.label, y->label, isCandidate(v) && v.pathsPerSample == 1, isCandidate(v) ? 1 : 0});
        if (isCandidate(v) && v.pathsPerSample > 1)
            if (const StudyVariant* ys = yardstickFor(variants, v, v.pathsPerSample))
                pairs.push_back({v.label, ys->label, true, v.pathsPerSample});
        // ears-orbit against ears (the same estimator and sampler): symmetric copies against independent directions.
        if (v.splitting == SplittingMode::EarsOrbit)
            for (const StudyVariant& w : variants)
                if (w.splitting == SplittingMode::Ears && w.estimator == v.estimator && w.sampler == v.sampler) {
                    pairs.push_back({v.label, w.label, false, 0});
                    break;
                }
    }
    out.insert(out.end(), pairs.begin(), pairs.end());
    return out;
}

std::optional<RatioInterval> compareVariants(const std::vector<StudyRow>& rows, const std::string& variant, const std::string& against,
                                             std::uint32_t spp, ErrorMeasure measure, ReferenceError reference) {
    std::map<int, const StudyRow*> a, b;
    for (const StudyRow& r : rows)
        if (r.spp == spp) {
            if (r.variant == variant) a[r.repeat] = &r;
            if (r.variant == against) b[r.repeat] = &r;
        }
    std::vector<double> errA, costA, errB, costB;
    double referenceSd = 0;  // the same in every row of a study: the reference's error in each MSE (StudyRow::referenceSd)
    for (const auto& [rep, ra] : a)
        if (const auto it = b.find(rep); it != b.end()) {
            const StudyRow* rb = it->second;
            errA.push_back(measure == ErrorMeasure::Mse ? ra->mse : ra->relMse);
            errB.push_back(measure == ErrorMeasure::Mse ? rb->mse : rb->relMse);
            costA.push_back(ra->cost);
            costB.push_back(rb->cost);
            referenceSd = std::max({referenceSd, ra->referenceSd, rb->referenceSd});
        }
    // Only the MSE has the reference's noise removed (study/measure.cpp) and so its realized error to carry;
    // the relative MSE's intervals stay the repeats' own.
    const bool shared = measure == ErrorMeasure::Mse && reference == ReferenceError::Included;
    return efficiencyRatio(errA, costA, errB, costB, shared ? referenceSd : 0.0);
}

bool biasedAt(const std::vector<StudyRow>& rows, const std::string& variant, std::uint32_t spp) {
    return std::any_of(rows.begin(), rows.end(),
                       [&](const StudyRow& r) { return r.variant == variant && r.spp == spp && r.groupBiasSignificant; });
}

std::set<std::string> variantsToRepeat(const std::vector<StudyRow>& rows, std::uint32_t spp, const std::vector<VariantPair>& comparisons,
                                       double target) {
    std::set<std::string> need;
    for (const VariantPair& c : comparisons) {
        if (biasedAt(rows, c.variant, spp) || biasedAt(rows, c.against, spp)) continue;
        const auto r = compareVariants(rows, c.variant, c.against, spp, ErrorMeasure::Mse, ReferenceError::Left);
        if (r && settled(*r, target)) continue;
        need.insert(c.variant);
        need.insert(c.against);
    }
    return need;
}

int repeatsOf(const std::vector<StudyRow>& rows, const std::string& variant, std::uint32_t spp) {
    return static_cast<int>(std::count_if(rows.begin(), rows.end(), [&](const StudyRow& r) { return r.variant == variant && r.spp == spp; }));
}

}  // namespace symphong
