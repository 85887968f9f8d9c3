#include "estimators/registry.h"

#include "estimators/basic.h"
#include "estimators/symmetric.h"
#include "estimators/symmetric_mix.h"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>

namespace symphong {

namespace {

// Traits, spelled out: {has a density, set estimator, own sampler, role, yardstick, takes an orbit}.
constexpr EstimatorTraits kPlain{true, false, "", EstimatorRole::Other, false};
constexpr EstimatorTraits kBaseline{true, false, "", EstimatorRole::Baseline, false};
constexpr EstimatorTraits kYardstick{true, false, "", EstimatorRole::Baseline, true};
constexpr EstimatorTraits kStratifiedTraits{true, false, "stratified", EstimatorRole::Baseline, false};
constexpr EstimatorTraits kCandidate{true, true, "", EstimatorRole::Candidate, false};
constexpr EstimatorTraits kCandidateWithoutDensity{false, true, "", EstimatorRole::Candidate, false};
constexpr EstimatorTraits kCandidateWithOrbit{true, true, "", EstimatorRole::Candidate, false, true};

// The table: one entry per estimator.
const EstimatorEntry kEstimators[] = {
    {"uniform", "uniform hemisphere directions, p = 1/(2 pi)", kPlain, makeUniformEstimator},
    {"cosine", "cosine-weighted directions, p = cos/pi", kBaseline, makeCosineEstimator},
    {"stratified", "cosine directions under the stratified sampler (whatever --sampler says)", kStratifiedTraits, makeStratifiedEstimator},
    {"phong", "Phong lobe importance sampling: diffuse or specular lobe chosen by albedo", kYardstick, makePhongLobeEstimator},
    {"paper", "the paper's symmetric estimator, Eq. (4) + (7), exactly as printed (biased)", kCandidateWithoutDensity, makePaperEstimator},
    {"symmetric", "corrected symmetric estimator: 16 pieces + 8 rotated triangles, exact maps, MIS", kCandidate, makeSymmetricEstimator},
    {"symmetric-shifted", "as symmetric, each symmetric copy from its own shifted (u,v)", kCandidate, makeSymmetricShiftedEstimator},
    {"symmetric-mix",
     "symmetric sampling with phong's mixture: pieces by projected solid angle, lobe vs\n"
     "             diffuse by albedo (stratified), 8 wedges of the exact lobe; orbits of --symmetric-orbit copies",
     kCandidateWithOrbit, makeSymmetricMixEstimator},
};

}  // namespace

std::span<const EstimatorEntry> estimatorTable() { return kEstimators; }

const EstimatorEntry* findEstimator(std::string_view name) {
    for (const EstimatorEntry& e : kEstimators)
        if (e.name == name) return &e;
    return nullptr;
}

const std::vector<std::string>& estimatorNames() {
    static const std::vector<std::string> names = [] {
        std::vector<std::string> out;
        for (const EstimatorEntry& e : kEstimators) out.emplace_back(e.name);
        return out;
    }();
    return names;
}

const EstimatorEntry& estimatorEntry(std::string_view name) {
    if (const EstimatorEntry* e = findEstimator(name)) return *e;
    throw std::invalid_argument(fmt::format("unknown estimator '{}' (valid: {})", name, fmt::join(estimatorNames(), ", ")));
}

std::string_view yardstickEstimator() {
    const auto it =
        std::find_if(std::begin(kEstimators), std::end(kEstimators), [](const EstimatorEntry& e) { return e.traits.yardstick; });
    return it == std::end(kEstimators) ? kEstimators[0].name : it->name;
}

std::string estimatorHelp() {
    std::string out;
    for (const EstimatorEntry& e : kEstimators) out += fmt::format("{}{:<10} - {}", out.empty() ? "" : "\n", e.name, e.help);
    return out;
}

std::string_view symmetricModeName(SymmetricMode mode) { return mode == SymmetricMode::Spread ? "spread" : "branch"; }

SymmetricMode parseSymmetricMode(std::string_view name) {
    if (name == "branch") return SymmetricMode::Branch;
    if (name == "spread") return SymmetricMode::Spread;
    throw std::invalid_argument(fmt::format("unknown symmetric mode '{}' (valid: branch, spread)", name));
}

bool hasSymmetricModes(std::string_view name) {
    const EstimatorEntry* e = findEstimator(name);
    return e && e->traits.setEstimator;
}

std::string effectiveSampler(const Estimator& estimator, const std::string& requested) {
    return estimator.requiredSampler().empty() ? requested : std::string(estimator.requiredSampler());
}

std::unique_ptr<Estimator> makeEstimator(std::string_view name, const EstimatorOptions& options) {
    return estimatorEntry(name).create(options);
}

}  // namespace symphong
