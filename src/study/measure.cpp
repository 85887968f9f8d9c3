// The measurement of one render against the reference (a row: bias, MSE with the reference's own noise
// removed, relMSE, its cost and efficiency, the render's own pixel variance). The group columns (bias over
// the repeats, pixel variance across them) are filled by study.cpp as repeats arrive.
#include "study/study_parts.h"

#include <algorithm>
#include <cmath>

namespace symphong {

StudyRow measureRow(const StudyConfig& c, const std::string& sceneName, const StudyVariant& variant, std::uint32_t spp, int rep,
                    const RenderResult& r, const Reference& ref) {
    StudyRow row;
    row.scene = sceneName;
    row.estimator = variant.estimator;
    row.variant = variant.label;
    row.sampler = variant.sampler;
    row.mode = std::string(symmetricModeName(variant.mode));
    row.spp = spp;
    row.split = variant.split;
    row.repeat = rep;
    row.width = c.width;
    row.height = c.height;
    row.seconds = r.stats.seconds;
    row.cpuSeconds = r.stats.cpuSeconds;
    row.rays = r.stats.rays;
    row.samples = r.stats.samples;
    row.paths = r.stats.paths;
    row.orbit = variant.orbit;
    row.cost = c.cost == StudyCost::Wall ? r.stats.seconds : c.cost == StudyCost::Rays ? static_cast<double>(r.stats.rays) : r.stats.cpuSeconds;
    const MeanWithError m = meanLuminance(r.image, &r.variance);
    row.meanLuminance = m.mean;
    row.meanStdError = m.stdError;
    row.relativeBias = ref.mean.mean != 0 ? (m.mean - ref.mean.mean) / ref.mean.mean : 0.0;
    const ImageError err = imageError(r.image, ref.image);
    row.mseRaw = err.mse;
    // Remove the reference's own noise from the error; where that would leave less than 5% of the raw
    // error the reference is too noisy to say more (the report warns).
    row.mse = std::max(err.mse - ref.noise, 0.05 * err.mse);
    row.referenceSd = ref.noiseSd;
    row.rmse = std::sqrt(row.mse);
    row.relMse = err.relMse;
    row.efficiency = 1.0 / (row.mse * std::max(row.cost, 1e-9));
    row.efficiencyRel = row.relMse > 0 ? 1.0 / (row.relMse * std::max(row.cost, 1e-9)) : 0.0;
    for (const Color& v : r.variance.pixels)
        row.pixelVarianceWithin += luminanceVariance(v) / static_cast<double>(r.variance.pixels.size());
    return row;
}

void GroupImages::add(const Image& image) {
    if (sum.empty()) sum.assign(image.pixels.size(), 0.0), sumSq.assign(image.pixels.size(), 0.0);
    for (std::size_t i = 0; i < sum.size(); ++i) {
        const double y = luminance(image.pixels[i]);
        sum[i] += y;
        sumSq[i] += y * y;
    }
    ++images;
}

double GroupImages::pixelVariance() const {
    const double R = images;
    double total = 0;
    for (std::size_t i = 0; i < sum.size(); ++i) total += std::max(0.0, (sumSq[i] - sum[i] * sum[i] / R) / (R - 1));
    return sum.empty() ? 0.0 : total / static_cast<double>(sum.size());
}

}  // namespace symphong
