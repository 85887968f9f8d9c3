#include "estimators/symmetric_mix.h"

#include "estimators/basic.h"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>

namespace symphong {

using namespace separation;

namespace {

/// u in [lo, lo + width) rescaled onto [0, 1).
double rescale(double u, double lo, double width) { return std::min((u - lo) / width, kOneBelow); }

}  // namespace

// The coset's first octant is folded into u (8/R equal parts); what is left of u and v is the canonical
// point. The family is not folded into (u,v): it comes from t, so that the copies of one orbit can split
// between the families while sharing p.
SymmetricMixEstimator::Orbit SymmetricMixEstimator::makeOrbit(Point2 uv, double t, int orbit) {
    Orbit o;
    o.t = t;
    o.p = uv;
    const int cosets = 8 / orbit;
    if (cosets > 1) {
        o.base = std::min(cosets - 1, static_cast<int>(uv.u * cosets));
        o.p.u = rescale(uv.u, static_cast<double>(o.base) / cosets, 1.0 / cosets);
    }
    return o;
}

namespace {

/// j's bits reversed within log2(R) bits: 0 4 2 6 1 5 3 7 for R = 8 (antipodal pairs first).
int reverseWithin(int j, int orbit) {
    int r = 0;
    for (int bit = 1, rbit = orbit >> 1; bit < orbit; bit <<= 1, rbit >>= 1)
        if (j & bit) r |= rbit;
    return r;
}

}  // namespace

// Copy j: octant base + (8/R) bitreverse(j); family from t_j = frac(t + j/R) (diffuse below P_d, as
// `phong` folds it); then the family's octant-0 map of p (octantCosineMap: triangle or quadrangle in
// proportion to their projected solid angles; phongWedgeMap: wedge 0 of the exact lobe), carried to the
// octant by its signed permutation, and for the lobe rotated onto the mirror direction (R_X(theta_s)).
// Each family's map of p is computed once per orbit, on first use: the copies differ by sign flips and
// swaps only (the paper's reuse by symmetry).
SymmetricMixEstimator::OrbitCopies::OrbitCopies(const PhongMaterial& m, const Vec3& wo, const Orbit& o, int orbit)
    : m_(m), wo_(wo), o_(o), orbit_(orbit), pd_(PhongLobeEstimator::diffuseProbability(m)) {}

Vec3 SymmetricMixEstimator::OrbitCopies::operator()(int j) {
    const int octant = o_.base + (8 / orbit_) * reverseWithin(j, orbit_);
    double t = o_.t + static_cast<double>(j) / orbit_;
    if (t >= 1.0) t -= 1.0;
    if (t < pd_) {
        if (!haveDiffuse_) diffuse_ = octantCosineMap(o_.p), haveDiffuse_ = true;
        return toOctant(diffuse_, octant);
    }
    if (!haveLobe_) {
        lobeDir_ = phongWedgeMap(o_.p, m_.exponent);
        frame_ = LobeFrame::fromMirror(mirrorDirection(wo_));
        haveLobe_ = true;
    }
    return frame_.toLocal(toOctant(lobeDir_, octant));
}

Vec3 SymmetricMixEstimator::copy(const PhongMaterial& m, const Vec3& wo, const Orbit& o, int j, int orbit) {
    return OrbitCopies(m, wo, o, orbit)(j);
}

// q(w) = P_d cos(theta)/pi + (1 - P_d) (n+1)/(2 pi) cos^n(alpha): uniform octant x (octantCosineMap's
// 8 cos/pi on octant 0, or phongWedgeMap's 8 (n+1)/(2 pi) cos^n on wedge 0) = cosine sampling or the whole
// Phong lobe, mixed by the family's probability. The same function as `phong`'s density.
double SymmetricMixEstimator::directionDensity(const ShadingContext& ctx, const Vec3& wi) {
    return PhongLobeEstimator::directionPdf(ctx, wi);
}

void SymmetricMixEstimator::push(const ShadingContext& ctx, const Vec3& wi, double copies, DirectionList& out) const {
    // pushWeighted(ctx, wi, copies x directionDensity(ctx, wi), out)'s bits with one pow instead of two. A lobe
    // direction below the surface carries no light (weigh returns before its density is computed).
    PhongLobeEstimator::weigh(ctx, wi, out, copies);
}

void SymmetricMixEstimator::sample(const ShadingContext& ctx, SampleStream& samples, DirectionList& out) const {
    const PhongMaterial& m = *ctx.material;
    if (!ctx.branch) {
        // Deeper bounces: the samples of a pixel are at different places by then, so there is no orbit to
        // share (R = 1). The direction has the same density q either way; `phong`'s warps draw it at
        // less cost than the separation's maps (one concentric-disk or lobe map instead of a piece map
        // and a rotation), so they are used here, and its weight with one pow (PhongLobeEstimator::weigh:
        // push(ctx, wi, 1, out)'s bits): the vertex is `phong`'s, so that a comparison of the two
        // estimators sees their first hits only.
        PhongLobeEstimator::weigh(ctx, PhongLobeEstimator::sampleDirection(ctx, samples.get2D()), out);
        return;
    }
    if (mode_ == SymmetricMode::Branch) {
        // The whole orbit from one camera sample: R copies of one point, each weighted f cos / (R q).
        const Vec3 p = samples.get3D();  // under sobol, (u, v, t) are Sobol' dimensions 0-2 of one index
        OrbitCopies copies(m, ctx.wo, makeOrbit({p.x, p.y}, p.z, orbit_), orbit_);
        for (int j = 0; j < orbit_; ++j) push(ctx, copies(j), static_cast<double>(orbit_), out);
        return;
    }
    // Spread mode at the first hit: the pixel's samples in rounds of R; this sample is copy
    // j = pi_r(i mod R) of its round's orbit, whose point and family offset are drawn once per round from
    // patterns over the rounds (so both are stratified over the rounds).
    const std::uint32_t R = static_cast<std::uint32_t>(orbit_);
    const std::uint32_t j = samples.patternEntry(R);
    const Vec3 p = samples.roundPoint3D(R);
    push(ctx, OrbitCopies(m, ctx.wo, makeOrbit({p.x, p.y}, p.z, orbit_), orbit_)(static_cast<int>(j)), 1.0, out);
}

double SymmetricMixEstimator::misPdf(const ShadingContext& ctx, const Vec3& wi) const {
    if (wi.z <= 0) return 0.0;
    const double copies = ctx.branch && mode_ == SymmetricMode::Branch ? static_cast<double>(orbit_) : 1.0;
    return copies * directionDensity(ctx, wi);
}

std::unique_ptr<Estimator> makeSymmetricMixEstimator(const EstimatorOptions& o) {
    if (o.symmetricOrbit != 1 && o.symmetricOrbit != 2 && o.symmetricOrbit != 4 && o.symmetricOrbit != 8)
        throw std::invalid_argument(fmt::format("--symmetric-orbit {} is not one of 1, 2, 4, 8", o.symmetricOrbit));
    return std::make_unique<SymmetricMixEstimator>(o.symmetricMode, o.symmetricOrbit);
}

}  // namespace symphong
