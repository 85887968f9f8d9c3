#include "estimators/basic.h"
#include "estimators/estimator.h"
#include "estimators/symmetric.h"
#include "estimators/symmetric_mix.h"

#include <fmt/format.h>

#include <stdexcept>

namespace symphong {

const std::vector<std::string>& estimatorNames() {
    static const std::vector<std::string> names = {"uniform", "cosine", "stratified", "phong", "paper", "symmetric", "symmetric-shifted", "symmetric-mix"};
    return names;
}

std::string estimatorHelp() {
    return "uniform    - uniform hemisphere directions, p = 1/(2 pi)\n"
           "cosine     - cosine-weighted directions, p = cos/pi\n"
           "stratified - cosine directions under the stratified sampler (whatever --sampler says)\n"
           "phong      - Phong lobe importance sampling: diffuse or specular lobe chosen by albedo\n"
           "paper      - the paper's symmetric estimator, Eq. (4) + (7), exactly as printed (biased)\n"
           "symmetric  - corrected symmetric estimator: 16 pieces + 8 rotated triangles, exact maps, MIS\n"
           "symmetric-shifted - as symmetric, each symmetric copy from its own shifted (u,v)\n"
           "symmetric-mix - symmetric sampling with phong's mixture: pieces by projected solid angle, lobe vs\n"
           "             diffuse by albedo (stratified), 8 wedges of the exact lobe; orbits of --symmetric-orbit copies";
}

std::string_view symmetricModeName(SymmetricMode mode) { return mode == SymmetricMode::Spread ? "spread" : "branch"; }

SymmetricMode parseSymmetricMode(std::string_view name) {
    if (name == "branch") return SymmetricMode::Branch;
    if (name == "spread") return SymmetricMode::Spread;
    throw std::invalid_argument(fmt::format("unknown symmetric mode '{}' (valid: branch, spread)", name));
}

bool hasSymmetricModes(std::string_view name) { return name == "paper" || name == "symmetric" || name == "symmetric-shifted" || name == "symmetric-mix"; }

std::string effectiveSampler(const Estimator& estimator, const std::string& requested) {
    return estimator.requiredSampler().empty() ? requested : std::string(estimator.requiredSampler());
}

std::unique_ptr<Estimator> makeEstimator(std::string_view name, const EstimatorOptions& options) {
    if (options.symmetricN < 1 || options.symmetricN > 4096)
        throw std::invalid_argument(fmt::format("--symmetric-n {} is out of range (1..4096)", options.symmetricN));
    if (options.symmetricOrbit != 1 && options.symmetricOrbit != 2 && options.symmetricOrbit != 4 && options.symmetricOrbit != 8)
        throw std::invalid_argument(fmt::format("--symmetric-orbit {} is not one of 1, 2, 4, 8", options.symmetricOrbit));
    if (name == "uniform") return std::make_unique<UniformEstimator>();
    if (name == "cosine") return std::make_unique<CosineEstimator>();
    if (name == "stratified") return std::make_unique<CosineEstimator>(true);
    if (name == "phong") return std::make_unique<PhongLobeEstimator>();
    if (name == "paper") return std::make_unique<PaperEstimator>(options.symmetricN, options.paperRefined, options.symmetricMode);
    if (name == "symmetric") return std::make_unique<SymmetricEstimator>(options.symmetricN, false, options.symmetricMode);
    if (name == "symmetric-shifted") return std::make_unique<SymmetricEstimator>(options.symmetricN, true, options.symmetricMode);
    if (name == "symmetric-mix") return std::make_unique<SymmetricMixEstimator>(options.symmetricMode, options.symmetricOrbit);
    throw std::invalid_argument(fmt::format("unknown estimator '{}' (valid: {})", name, fmt::join(estimatorNames(), ", ")));
}

}  // namespace symphong
