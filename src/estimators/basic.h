// estimators/basic.h — the classic one-direction strategies: uniform and cosine-weighted hemisphere
// sampling, cosine sampling stratified across a pixel's samples, and Phong-lobe importance sampling.
#pragma once

#include "estimators/estimator.h"

namespace symphong {

/// Uniform hemisphere sampling, p = 1/(2 pi).
class UniformEstimator final : public Estimator {
public:
    std::string_view name() const override { return "uniform"; }
    void sample(const ShadingContext& ctx, Rng& rng, std::vector<DirectionSample>& out) const override;
    double misPdf(const ShadingContext& ctx, const Vec3& wi) const override;
};

/// Cosine-weighted hemisphere sampling, p = cos(theta)/pi.
class CosineEstimator final : public Estimator {
public:
    std::string_view name() const override { return "cosine"; }
    void sample(const ShadingContext& ctx, Rng& rng, std::vector<DirectionSample>& out) const override;
    double misPdf(const ShadingContext& ctx, const Vec3& wi) const override;
};

/// Cosine sampling whose unit-square points are jittered strata across a pixel: camera sample i of N
/// takes cell i of an nx x ny grid (nx ny = N, nx the largest divisor of N not above sqrt(N)). Only at
/// the first hit (depth 0); deeper bounces are plain cosine, since reusing the same cell index at every
/// depth would correlate the bounces of one path and bias the image.
class StratifiedEstimator final : public Estimator {
public:
    std::string_view name() const override { return "stratified"; }
    void sample(const ShadingContext& ctx, Rng& rng, std::vector<DirectionSample>& out) const override;
    double misPdf(const ShadingContext& ctx, const Vec3& wi) const override;

    /// The grid nx x ny used for N samples.
    static void grid(std::uint32_t n, int& nx, int& ny);
};

/// Phong-lobe importance sampling: the diffuse lobe (cosine) with probability
/// P_d = Y(rho_d) / (Y(rho_d) + Y(rho_s)), else the specular lobe cos^n(alpha) around the mirror
/// direction; weighted by the mixture density P_d cos/pi + (1-P_d) (n+1)/(2 pi) cos^n(alpha).
class PhongLobeEstimator final : public Estimator {
public:
    std::string_view name() const override { return "phong"; }
    void sample(const ShadingContext& ctx, Rng& rng, std::vector<DirectionSample>& out) const override;
    double misPdf(const ShadingContext& ctx, const Vec3& wi) const override;

    /// Probability of choosing the diffuse lobe for a material.
    static double diffuseProbability(const PhongMaterial& m);
    /// One direction of the mixture, before the horizon test (a lobe direction may point below it).
    static Vec3 sampleDirection(const ShadingContext& ctx, Rng& rng);
    /// The mixture's density over the whole sphere, matching sampleDirection.
    static double directionPdf(const ShadingContext& ctx, const Vec3& wi);
};

}  // namespace symphong
