// estimators/basic.h — the classic one-direction strategies: uniform and cosine-weighted hemisphere
// sampling (plain, or under the stratified sampler as `stratified`), and Phong-lobe importance sampling.
// Each draws one 2D value from the sample stream.
#pragma once

#include "estimators/estimator.h"

namespace symphong {

/// Appends wi with weight f cos / pdf and misPdf pdf, pdf the density of the call's direction set at wi
/// (K p for K directions); skips directions below the surface, without density, or with f = 0.
void pushWeighted(const ShadingContext& ctx, const Vec3& wi, double pdf, DirectionList& out);

/// Factories of the table in estimators/registry.cpp (none reads an option).
std::unique_ptr<Estimator> makeUniformEstimator(const EstimatorOptions&);
std::unique_ptr<Estimator> makeCosineEstimator(const EstimatorOptions&);
std::unique_ptr<Estimator> makeStratifiedEstimator(const EstimatorOptions&);
std::unique_ptr<Estimator> makePhongLobeEstimator(const EstimatorOptions&);

/// Uniform hemisphere sampling, p = 1/(2 pi).
class UniformEstimator final : public Estimator {
public:
    std::string_view name() const override { return "uniform"; }
    void sample(const ShadingContext& ctx, SampleStream& samples, DirectionList& out) const override;
    double misPdf(const ShadingContext& ctx, const Vec3& wi) const override;
};

/// Cosine-weighted hemisphere sampling, p = cos(theta)/pi. Named `stratified`, it is the same
/// estimator bound to the stratified sampler (jittered strata in every dimension pair, every depth).
class CosineEstimator final : public Estimator {
public:
    explicit CosineEstimator(bool stratified = false) : stratified_(stratified) {}
    std::string_view name() const override { return stratified_ ? "stratified" : "cosine"; }
    void sample(const ShadingContext& ctx, SampleStream& samples, DirectionList& out) const override;
    double misPdf(const ShadingContext& ctx, const Vec3& wi) const override;
    std::string_view requiredSampler() const override { return stratified_ ? "stratified" : ""; }

private:
    bool stratified_;
};

/// Phong-lobe importance sampling: the diffuse lobe (cosine) with probability
/// P_d = Y(rho_d) / (Y(rho_d) + Y(rho_s)), else the specular lobe cos^n(alpha) around the mirror
/// direction; weighted by the mixture density P_d cos/pi + (1-P_d) (n+1)/(2 pi) cos^n(alpha).
class PhongLobeEstimator final : public Estimator {
public:
    std::string_view name() const override { return "phong"; }
    void sample(const ShadingContext& ctx, SampleStream& samples, DirectionList& out) const override;
    double misPdf(const ShadingContext& ctx, const Vec3& wi) const override;
    bool drawsAhead(bool) const override { return true; }
    void drawAhead(const PhongMaterial* const* materials, const double* us, const double* vs, std::size_t n,
                   DirectionDraw* out) const override {
        drawDirections(materials, us, vs, n, out);
    }
    void sampleDrawn(const ShadingContext& ctx, const DirectionDraw& draw, DirectionList& out) const override {
        weigh(ctx, placeDirection(ctx.wo, draw), out);
    }

    /// Probability of choosing the diffuse lobe for a material.
    static double diffuseProbability(const PhongMaterial& m);
    /// One direction of the mixture from one 2D value, before the horizon test (a lobe direction may
    /// point below it): the lobe choice is folded into u.u (diffuse when u.u < P_d, then rescaled to
    /// [0,1)), so the 2D value's stratification carries over to both lobes.
    static Vec3 sampleDirection(const ShadingContext& ctx, Point2 u) { return placeDirection(ctx.wo, drawDirection(*ctx.material, u)); }
    /// sampleDirection's steps that need only the material: the lobe's choice and the direction in the
    /// chosen lobe's own frame (the shading frame for the diffuse lobe).
    static DirectionDraw drawDirection(const PhongMaterial& m, Point2 u);
    /// A drawn direction in the shading frame: a lobe direction turned into the frame around wo's mirror.
    static Vec3 placeDirection(const Vec3& wo, const DirectionDraw& d);
    /// The mixture's density over the whole sphere, matching sampleDirection.
    static double directionPdf(const ShadingContext& ctx, const Vec3& wi);
    /// drawDirection for the n points with materials[i] (a null one's slot left as it was) from (us[i], vs[i]).
    static void drawDirections(const PhongMaterial* const* materials, const double* us, const double* vs, std::size_t n,
                               DirectionDraw* out);
    /// sample()'s direction wi (from sampleDirection) with its weight and density, appended to `out`: the same bits
    /// as pushWeighted(ctx, wi, copies x directionPdf(ctx, wi), out) where wi.z > 0, with one pow instead of two.
    /// `copies`: a power of two (1 for sample(); symmetric-mix's orbit of R directions), so the product is exact.
    static void weigh(const ShadingContext& ctx, const Vec3& wi, DirectionList& out, double copies = 1.0);
};

}  // namespace symphong
