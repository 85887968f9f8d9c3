#include "estimators/basic.h"
#include "estimators/estimator.h"

#include <fmt/format.h>

#include <stdexcept>

namespace symphong {

const std::vector<std::string>& estimatorNames() {
    static const std::vector<std::string> names = {"uniform", "cosine", "stratified", "phong"};
    return names;
}

std::string estimatorHelp() {
    return "uniform    - uniform hemisphere directions, p = 1/(2 pi)\n"
           "cosine     - cosine-weighted directions, p = cos/pi\n"
           "stratified - cosine directions from jittered strata across each pixel's samples (first hit)\n"
           "phong      - Phong lobe importance sampling: diffuse or specular lobe chosen by albedo";
}

std::unique_ptr<Estimator> makeEstimator(std::string_view name) {
    if (name == "uniform") return std::make_unique<UniformEstimator>();
    if (name == "cosine") return std::make_unique<CosineEstimator>();
    if (name == "stratified") return std::make_unique<StratifiedEstimator>();
    if (name == "phong") return std::make_unique<PhongLobeEstimator>();
    throw std::invalid_argument(fmt::format("unknown estimator '{}' (valid: {})", name, fmt::join(estimatorNames(), ", ")));
}

}  // namespace symphong
