#include "estimators/basic.h"

#include "math/frame.h"
#include "sampling/warp.h"
#include "sampling/warp_lanes.h"

#include <array>
#include <cmath>

namespace symphong {

void pushWeighted(const ShadingContext& ctx, const Vec3& wi, double pdf, DirectionList& out) {
    if (wi.z <= 0 || pdf <= 0) return;
    const Color f = evalPhong(*ctx.material, ctx.wo, wi);
    if (isBlack(f)) return;
    out.push_back({wi, f * (wi.z / pdf), pdf});
}

void UniformEstimator::sample(const ShadingContext& ctx, SampleStream& samples, DirectionList& out) const {
    const Vec3 wi = sampleUniformHemisphere(samples.get2D());
    pushWeighted(ctx, wi, uniformHemispherePdf(wi), out);
}
double UniformEstimator::misPdf(const ShadingContext&, const Vec3& wi) const { return uniformHemispherePdf(wi); }

void CosineEstimator::sample(const ShadingContext& ctx, SampleStream& samples, DirectionList& out) const {
    const Vec3 wi = sampleCosineHemisphere(samples.get2D());
    pushWeighted(ctx, wi, cosineHemispherePdf(wi), out);
}
double CosineEstimator::misPdf(const ShadingContext&, const Vec3& wi) const { return cosineHemispherePdf(wi); }

double PhongLobeEstimator::diffuseProbability(const PhongMaterial& m) {
    // Without a specular part, 1 without the division: d / (d + 0) is exactly 1 for d > 0, and 1 is the answer
    // for d = 0 too (the division's latency sat under every diffuse vertex's weight and densities).
    if (!m.hasSpecular()) return 1.0;
    const double d = luminance(m.rhoD), s = luminance(m.rhoS);
    return d + s > 0 ? d / (d + s) : 1.0;
}

namespace {

// The lobe choice is folded into u.u: [0, P_d) -> diffuse, [P_d, 1) -> specular, each rescaled to [0,1).
/// The diffuse lobe's 2D value (u.u < P_d).
Point2 diffuseValue(Point2 u, double pd) { return {std::min(u.u / pd, kOneBelow), u.v}; }
/// The specular lobe's draw (u.u >= P_d): its direction around +Z, to be turned into the mirror's frame.
DirectionDraw lobeDraw(Point2 u, double pd, double exponent) {
    return {samplePhongLobe({std::min((u.u - pd) / (1.0 - pd), kOneBelow), u.v}, exponent), true};
}

}  // namespace

DirectionDraw PhongLobeEstimator::drawDirection(const PhongMaterial& m, Point2 u) {
    const double pd = diffuseProbability(m);
    if (u.u < pd) return {sampleCosineHemisphere(diffuseValue(u, pd)), false};
    return lobeDraw(u, pd, m.exponent);
}

Vec3 PhongLobeEstimator::placeDirection(const Vec3& wo, const DirectionDraw& d) {
    return d.aroundMirror ? Frame::fromNormal(mirrorDirection(wo)).toWorld(d.local) : d.local;
}

// drawDirection for n points: the lobe directions one by one, the diffuse ones together in the warp's lanes
// (sampling/warp_lanes.h: the same bits), a chunk at a time. The points' chains (a division, a square root, pow
// or the sine's polynomial) are independent of each other: the lanes take eight at once, and a loop of them the
// processor overlaps (docs/performance.md "The estimator's directions ahead").
void PhongLobeEstimator::drawDirections(const PhongMaterial* const* materials, const double* us, const double* vs, std::size_t n,
                                        DirectionDraw* out) {
    constexpr std::size_t kChunk = 64;
    std::array<double, kChunk> diffuseU, diffuseV;
    std::array<std::size_t, kChunk> diffuseAt;
    std::array<Vec3, kChunk> diffuse;
    for (std::size_t first = 0; first < n; first += kChunk) {
        const std::size_t end = std::min(n, first + kChunk);
        std::size_t m = 0;
        for (std::size_t i = first; i < end; ++i) {
            if (!materials[i]) continue;
            const PhongMaterial& mat = *materials[i];
            const double pd = diffuseProbability(mat);
            const Point2 u{us[i], vs[i]};
            if (u.u < pd) {
                const Point2 d = diffuseValue(u, pd);
                diffuseU[m] = d.u;
                diffuseV[m] = d.v;
                diffuseAt[m++] = i;
            } else {
                out[i] = lobeDraw(u, pd, mat.exponent);
            }
        }
        cosineHemisphereDirections(diffuseU.data(), diffuseV.data(), m, diffuse.data());
        for (std::size_t j = 0; j < m; ++j) {  // field by field: a whole DirectionDraw went through the stack, a wait on memory
            DirectionDraw& d = out[diffuseAt[j]];
            d.local = diffuse[j];
            d.aroundMirror = false;
        }
    }
}

double PhongLobeEstimator::directionPdf(const ShadingContext& ctx, const Vec3& wi) {
    const PhongMaterial& m = *ctx.material;
    const double pd = diffuseProbability(m);
    double pdf = pd * cosineHemispherePdf(wi);
    if (pd < 1.0) {
        const Vec3 r = mirrorDirection(ctx.wo);
        pdf += (1.0 - pd) * phongLobePdf(dot(r, wi), m.exponent);
    }
    return pdf;
}

void PhongLobeEstimator::sample(const ShadingContext& ctx, SampleStream& samples, DirectionList& out) const {
    weigh(ctx, sampleDirection(ctx, samples.get2D()), out);
}

// pushWeighted(ctx, wi, directionPdf(ctx, wi), out) with one pow instead of two: the mixture density
//   p = P_d cos(theta)/pi + (1 - P_d) (n+1)/(2 pi) c^n   and the BRDF   f = rho_d/pi + rho_s (n+2)/(2 pi) c^n
// share c^n, c = cos(alpha) = r . wi (the same value phongCosAlpha gives, so the same bits as the two calls).
void PhongLobeEstimator::weigh(const ShadingContext& ctx, const Vec3& wi, DirectionList& out, double copies) {
    if (wi.z <= 0 || ctx.wo.z <= 0) return;
    const PhongMaterial& m = *ctx.material;
    const double pd = diffuseProbability(m);
    const double c = dot(mirrorDirection(ctx.wo), wi);
    // The material's test first: c > 0 is a coin toss per sample where the lobe is absent (a diffuse surface).
    const bool lobe = (pd < 1.0 || m.hasSpecular()) && c > 0;
    const double cn = lobe ? std::pow(c, m.exponent) : 0.0;
    // cn = 0 where c <= 0 (and pd < 1 or a specular part make `lobe` c > 0): the lobe's terms below add
    // exactly +0 there, without a test of c (which would be the coin toss again).
    double pdf = pd * (wi.z * kInvPi);
    if (pd < 1.0) pdf += (1.0 - pd) * ((m.exponent + 1.0) / kTwoPi * cn);
    pdf *= copies;
    if (pdf <= 0) return;
    Color f = m.rhoD * kInvPi;
    if (m.hasSpecular()) f += m.rhoS * ((m.exponent + 2.0) / kTwoPi * cn);
    if (isBlack(f)) return;
    out.push_back({wi, f * (wi.z / pdf), pdf});
}

double PhongLobeEstimator::misPdf(const ShadingContext& ctx, const Vec3& wi) const { return wi.z > 0 ? directionPdf(ctx, wi) : 0.0; }

std::unique_ptr<Estimator> makeUniformEstimator(const EstimatorOptions&) { return std::make_unique<UniformEstimator>(); }
std::unique_ptr<Estimator> makeCosineEstimator(const EstimatorOptions&) { return std::make_unique<CosineEstimator>(); }
std::unique_ptr<Estimator> makeStratifiedEstimator(const EstimatorOptions&) { return std::make_unique<CosineEstimator>(true); }
std::unique_ptr<Estimator> makePhongLobeEstimator(const EstimatorOptions&) { return std::make_unique<PhongLobeEstimator>(); }

}  // namespace symphong
