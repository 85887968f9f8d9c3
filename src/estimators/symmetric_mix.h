// estimators/symmetric_mix.h — `symmetric-mix`: the paper's symmetric sampling with the three causes of
// its losses to Phong-lobe sampling removed (docs/estimators.md, section 10). The structure is the
// paper's: the hemisphere separated into 8 triangles + 8 quadrangles, a lobe covered by 8 pieces rotated
// onto the mirror direction, and one point (u,v) reused in every octant by the signed permutations.
// What changes:
//  1. the diffuse pieces are drawn in proportion to their projected solid angle (triangle Phi_T,
//     quadrangle Phi_Q in each octant), so the diffuse family is exactly cosine sampling;
//  2. diffuse against lobe is chosen in proportion to the albedos, as `phong` does, from a family offset
//     that is the third coordinate of the orbit's point (Sampler::value3D), so that it is stratified over
//     a pixel's samples jointly with the directions;
//  3. the lobe pieces are the 8 azimuth wedges of the exact Phong lobe (they cover all of it), not the
//     cube face's triangles.
// One direction then has the mixture density q = P_d cos/pi + (1 - P_d) (n+1)/(2 pi) cos^n(alpha) (the
// same as `phong`'s), which is the density MIS with light sampling uses. What the symmetry adds is the
// joint structure of a group of directions: an orbit of R = 1, 2, 4 or 8 copies of one canonical point
// (the octant's coset of a subgroup of the 8 signed permutations), traced together from one camera
// sample (branch mode) or spread over R consecutive camera samples of a pixel (spread mode).
#pragma once

#include "estimators/basic.h"
#include "estimators/estimator.h"
#include "sampling/separation.h"

namespace symphong {

/// Factory of the table in estimators/registry.cpp: reads the mode and the orbit (--symmetric-orbit: 1,
/// 2, 4 or 8).
std::unique_ptr<Estimator> makeSymmetricMixEstimator(const EstimatorOptions& options);

class SymmetricMixEstimator final : public Estimator {
public:
    /// orbit: R, the number of symmetric copies of one point used together (1, 2, 4 or 8).
    explicit SymmetricMixEstimator(SymmetricMode mode = SymmetricMode::Branch, int orbit = 2) : mode_(mode), orbit_(orbit) {}
    std::string_view name() const override { return "symmetric-mix"; }
    void sample(const ShadingContext& ctx, SampleStream& samples, DirectionList& out) const override;
    double misPdf(const ShadingContext& ctx, const Vec3& wi) const override;
    bool returnsSets() const override { return mode_ == SymmetricMode::Branch && orbit_ > 1; }
    std::uint32_t largestSet() const override { return returnsSets() ? static_cast<std::uint32_t>(orbit_) : 1; }
    std::uint32_t spreadSetSize(const ShadingContext&) const override {
        return mode_ == SymmetricMode::Spread ? static_cast<std::uint32_t>(orbit_) : 1u;
    }
    /// Deeper vertices (ctx.branch false) are `phong`'s, bit for bit (sample()): drawn ahead as its are.
    bool drawsAhead(bool branch) const override { return !branch; }
    void drawAhead(const PhongMaterial* const* materials, const double* us, const double* vs, std::size_t n,
                   DirectionDraw* out) const override {
        PhongLobeEstimator::drawDirections(materials, us, vs, n, out);
    }
    void sampleDrawn(const ShadingContext& ctx, const DirectionDraw& draw, DirectionList& out) const override {
        PhongLobeEstimator::weigh(ctx, PhongLobeEstimator::placeDirection(ctx.wo, draw), out);
    }

    /// One orbit: the canonical point p (in octant 0 of the diffuse pieces or of the lobe's wedges), the
    /// coset's first octant `base` (in [0, 8/R)) and the family offset t. Copy j of R takes the family
    /// diffuse when frac(t + j/R) < P_d, else the lobe, so an orbit's copies split between the families
    /// in proportion to P_d (stratified), and copies of one family share p (the symmetric reuse).
    struct Orbit {
        Point2 p;
        int base = 0;
        double t = 0;
    };
    /// The orbit of R copies from the point (u,v) and the family offset t: base folded into u.
    static Orbit makeOrbit(Point2 uv, double t, int orbit);
    /// The copies of one orbit at one shading point. Copy j (0..R-1) of R: its octant
    /// base + (8/R) bitreverse(j) (consecutive copies are antipodal pairs first), its family from
    /// frac(t + j/R); the direction in the local frame (a lobe direction may point below the surface).
    class OrbitCopies {
    public:
        OrbitCopies(const PhongMaterial& m, const Vec3& wo, const Orbit& o, int orbit);
        Vec3 operator()(int j);

    private:
        const PhongMaterial& m_;
        Vec3 wo_;
        Orbit o_;
        int orbit_;
        double pd_;
        bool haveDiffuse_ = false, haveLobe_ = false;
        Vec3 diffuse_, lobeDir_;
        separation::LobeFrame frame_;
    };
    /// Copy j of the orbit o of R at a point seen from wo (OrbitCopies, for one copy).
    static Vec3 copy(const PhongMaterial& m, const Vec3& wo, const Orbit& o, int j, int orbit);
    /// The mixture density of one direction (solid angle), over the whole sphere: `phong`'s.
    static double directionDensity(const ShadingContext& ctx, const Vec3& wi);

private:
    void push(const ShadingContext& ctx, const Vec3& wi, double copies, DirectionList& out) const;

    SymmetricMode mode_;
    int orbit_;
};

}  // namespace symphong
