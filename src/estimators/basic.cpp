#include "estimators/basic.h"

#include "math/frame.h"
#include "sampling/warp.h"

#include <cmath>

namespace symphong {

namespace {

/// Appends wi with weight f cos / pdf (one direction per call, so K = 1), skipping zero-weight ones.
void pushWeighted(const ShadingContext& ctx, const Vec3& wi, double pdf, std::vector<DirectionSample>& out) {
    if (wi.z <= 0 || pdf <= 0) return;
    const Color f = evalPhong(*ctx.material, ctx.wo, wi);
    if (isBlack(f)) return;
    out.push_back({wi, f * (wi.z / pdf), pdf});
}

}  // namespace

void UniformEstimator::sample(const ShadingContext& ctx, Rng& rng, std::vector<DirectionSample>& out) const {
    const Vec3 wi = sampleUniformHemisphere(rng.uniform2());
    pushWeighted(ctx, wi, uniformHemispherePdf(wi), out);
}
double UniformEstimator::misPdf(const ShadingContext&, const Vec3& wi) const { return uniformHemispherePdf(wi); }

void CosineEstimator::sample(const ShadingContext& ctx, Rng& rng, std::vector<DirectionSample>& out) const {
    const Vec3 wi = sampleCosineHemisphere(rng.uniform2());
    pushWeighted(ctx, wi, cosineHemispherePdf(wi), out);
}
double CosineEstimator::misPdf(const ShadingContext&, const Vec3& wi) const { return cosineHemispherePdf(wi); }

void StratifiedEstimator::grid(std::uint32_t n, int& nx, int& ny) {
    nx = 1;
    for (std::uint32_t d = 1; d * d <= n; ++d)
        if (n % d == 0) nx = static_cast<int>(d);
    ny = static_cast<int>(n / static_cast<std::uint32_t>(nx));
}

void StratifiedEstimator::sample(const ShadingContext& ctx, Rng& rng, std::vector<DirectionSample>& out) const {
    Point2 p = rng.uniform2();
    if (ctx.depth == 0 && ctx.sampleCount > 1) {
        int nx, ny;
        grid(ctx.sampleCount, nx, ny);
        const int cell = static_cast<int>(ctx.sampleIndex % ctx.sampleCount);
        p = jitterInStratum(cell % nx, cell / nx, nx, ny, p);
    }
    const Vec3 wi = sampleCosineHemisphere(p);
    // Inside cell i the density is N cos/pi. Weighting by cos/pi instead makes each sample N times its
    // cell's share of the integral, so the pixel's mean over its N samples (one per cell) is the whole
    // integral. MIS uses cos/pi too: a fixed function of wi, so the combination stays unbiased.
    pushWeighted(ctx, wi, cosineHemispherePdf(wi), out);
}
double StratifiedEstimator::misPdf(const ShadingContext&, const Vec3& wi) const { return cosineHemispherePdf(wi); }

double PhongLobeEstimator::diffuseProbability(const PhongMaterial& m) {
    const double d = luminance(m.rhoD), s = m.hasSpecular() ? luminance(m.rhoS) : 0.0;
    return d + s > 0 ? d / (d + s) : 1.0;
}

Vec3 PhongLobeEstimator::sampleDirection(const ShadingContext& ctx, Rng& rng) {
    const PhongMaterial& m = *ctx.material;
    const double choose = rng.uniform();
    const Point2 p = rng.uniform2();
    if (choose < diffuseProbability(m)) return sampleCosineHemisphere(p);
    const Vec3 r(-ctx.wo.x, -ctx.wo.y, ctx.wo.z);
    return Frame::fromNormal(r).toWorld(samplePhongLobe(p, m.exponent));
}

double PhongLobeEstimator::directionPdf(const ShadingContext& ctx, const Vec3& wi) {
    const PhongMaterial& m = *ctx.material;
    const double pd = diffuseProbability(m);
    double pdf = pd * cosineHemispherePdf(wi);
    if (pd < 1.0) {
        const Vec3 r(-ctx.wo.x, -ctx.wo.y, ctx.wo.z);
        pdf += (1.0 - pd) * phongLobePdf(dot(r, wi), m.exponent);
    }
    return pdf;
}

void PhongLobeEstimator::sample(const ShadingContext& ctx, Rng& rng, std::vector<DirectionSample>& out) const {
    const Vec3 wi = sampleDirection(ctx, rng);
    pushWeighted(ctx, wi, directionPdf(ctx, wi), out);
}

double PhongLobeEstimator::misPdf(const ShadingContext& ctx, const Vec3& wi) const {
    return wi.z > 0 ? directionPdf(ctx, wi) : 0.0;
}

}  // namespace symphong
