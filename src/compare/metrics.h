// compare/metrics.h — image error metrics against a reference, as pure functions of images: mean-image
// relative bias with its standard error, MSE / RMSE / relMSE, per-pixel variance across repeats.
// All work on luminance (Rec. 709) so that one number describes a colour image.
#pragma once

#include "io/image.h"

#include <vector>

namespace symphong {

struct ImageError {
    double mse = 0;     ///< mean over pixels of (Y - Y_ref)^2
    double rmse = 0;    ///< sqrt(mse)
    double relMse = 0;  ///< mean over pixels of (Y - Y_ref)^2 / (Y_ref^2 + 0.01)  (Rousselle et al.)
};

/// Variance of a pixel's luminance from its per-channel variances, taking the channels as fully
/// correlated (one path carries all three): (sum_c w_c sqrt(v_c))^2.
double luminanceVariance(const Color& channelVariance);

/// Errors of `img` against `ref` (same size; throws std::invalid_argument otherwise).
ImageError imageError(const Image& img, const Image& ref);

/// Mean luminance of an image, and the standard error of that mean from a per-pixel variance-of-mean
/// image (pixels independent, as in our renders: one random stream per pixel).
struct MeanWithError {
    double mean = 0, stdError = 0;
};
MeanWithError meanLuminance(const Image& img, const Image* varianceOfMean = nullptr);

/// Relative bias of a set of repeats against the reference: (mean of the repeats' image means -
/// reference mean) / reference mean, with its standard error and z = bias / error.
/// When every repeat knows its own error (renders with spp >= 2 estimate each pixel's variance), the
/// error combines those with the reference's, and the spread of the repeats if larger; `significant`
/// when |z| > 4. At 1 spp a render cannot know its error: then only the spread of R >= 2 repeats
/// measures it, with R - 1 degrees of freedom, and `significant` needs |z| above Student's t at the
/// same two-sided tail as 4 sigma (6.3e-5): 125.7 for R = 3, 17.5 for R = 5, 6.6 for R = 11. A single
/// repeat at 1 spp is never flagged.
struct BiasEstimate {
    double relative = 0, stdError = 0, z = 0;
    double threshold = 4;  ///< |z| above which the bias is significant
    bool significant = false;
};

/// Two-sided critical value of Student's t with `dof` degrees of freedom at the tail of 4 sigma.
double studentCritical(int dof);
BiasEstimate relativeBias(const std::vector<MeanWithError>& repeats, const MeanWithError& reference);

/// Mean over pixels of the variance of a pixel's luminance across R >= 2 repeats (unbiased, R - 1).
double pixelVarianceAcrossRepeats(const std::vector<const Image*>& repeats);

/// Mean over pixels of (Y_a - Y_b)^2 / 2 (luminance): for two renders that differ only in some of their
/// random numbers, an unbiased estimate of the mean pixel variance those numbers cause (the variance budget).
double halfSquaredDifference(const Image& a, const Image& b);

/// Per-pixel relative error |Y - Y_ref| / (Y_ref + 0.01), for heat maps.
std::vector<float> relativeErrorMap(const Image& img, const Image& ref);

}  // namespace symphong
