// The measurement of one render against the reference (a row: bias, MSE with the reference's own noise
// removed, relMSE, efficiency, the render's own pixel variance) and of a group of repeats (bias with its
// standard error, pixel variance across repeats, the variance budget's first-bounce part).
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
    row.rays = r.stats.rays;
    row.samples = r.stats.samples;
    const MeanWithError m = meanLuminance(r.image, &r.variance);
    row.meanLuminance = m.mean;
    row.meanStdError = m.stdError;
    row.relativeBias = ref.mean.mean != 0 ? (m.mean - ref.mean.mean) / ref.mean.mean : 0.0;
    const ImageError err = imageError(r.image, ref.image);
    row.mseRaw = err.mse;
    // Remove the reference's own noise from the error; where that would leave less than 5% of the raw
    // error the reference is too noisy to say more (the report warns).
    row.mse = std::max(err.mse - ref.noise, 0.05 * err.mse);
    row.rmse = std::sqrt(row.mse);
    row.relMse = err.relMse;
    row.efficiency = 1.0 / (row.mse * std::max(row.seconds, 1e-9));
    row.efficiencyRel = row.relMse > 0 ? 1.0 / (row.relMse * std::max(row.seconds, 1e-9)) : 0.0;
    for (const Color& v : r.variance.pixels)
        row.pixelVarianceWithin += luminanceVariance(v) / static_cast<double>(r.variance.pixels.size());
    return row;
}

void fillGroupColumns(std::vector<StudyRow>& rows, std::size_t firstRow, const std::vector<Image>& images,
                      const std::vector<MeanWithError>& means, const Reference& ref, double firstBounceVariance) {
    const BiasEstimate bias = relativeBias(means, ref.mean);
    std::vector<const Image*> ptrs;
    for (const Image& im : images) ptrs.push_back(&im);
    const double pv = pixelVarianceAcrossRepeats(ptrs);
    for (std::size_t i = firstRow; i < rows.size(); ++i) {
        StudyRow& row = rows[i];
        row.groupRelativeBias = bias.relative;
        row.groupBiasStdError = bias.stdError;
        row.groupBiasZ = bias.z;
        row.groupBiasThreshold = bias.threshold;
        row.groupBiasSignificant = bias.significant;
        row.groupPixelVariance = pv;
        row.groupFirstBounceVariance = firstBounceVariance;
    }
}

}  // namespace symphong
