#include "estimators/symmetric.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace symphong {

using namespace separation;

namespace {

double frac(double x) {
    const double f = x - std::floor(x);
    return f < 1.0 ? f : 0.0;
}

}  // namespace

// ---------------------------------------------------------------------------------------------------
// paper

double PaperEstimator::lobeNormalisation(double n, bool refined) {
    const double a = std::pow(std::sqrt(3.0) / 3.0, n + 1.0);
    if (!refined) return kTwoPi * (1.0 - a) / (n + 1.0);  // Eq. (6) with cos(theta_s,max) = 1/sqrt(3)
    const double b = std::pow(std::sqrt(2.0) / 2.0, n + 1.0);
    return kTwoPi / (n + 1.0) * (1.0 - 0.5 * (a + b));  // the conclusion's estimate
}

namespace {

/// The paper's three weighted directions from one point (u_j, v_j) and octant k, shared by the whole
/// estimate and by the one-direction form used at deeper bounces.
struct PaperTerms {
    Color rhoD, rhoS;      ///< the paper's rho_d (= ours / pi) and rho_s (= ours (n+2)/(2 pi))
    double diffuseScale;   ///< Eq. (4): pi / (48 N')
    double specularScale;  ///< Eq. (7): 2 pi (1 - (sqrt3/3)^(n+1)) / ((n+1) N), N = 8N'
    LobeFrame lobe;

    PaperTerms(const ShadingContext& ctx, int nPrime, bool refined)
        : rhoD(ctx.material->rhoD * kInvPi),
          rhoS(ctx.material->rhoS * ((ctx.material->exponent + 2.0) / kTwoPi)),
          diffuseScale(kPi / (48.0 * nPrime)),
          specularScale(PaperEstimator::lobeNormalisation(ctx.material->exponent, refined) / (8.0 * nPrime)),
          lobe(LobeFrame::fromMirror(mirrorDirection(ctx.wo))) {}

    // Each takes the point's map image in octant 0 (computed once per point) and its weight w(u,v).
    /// (1/2) L_tri w(u,v) of Eq. (4), from paperTriangleMap.
    DirectionSample triangle(const Vec3& tri, double w, int k) const { return {toOctant(tri, k), rhoD * (diffuseScale * 0.5 * w), 0.0}; }
    /// L_quad w(u,v) of Eq. (4), from paperQuadrangleMap.
    DirectionSample quadrangle(const Vec3& quad, double w, int k) const { return {toOctant(quad, k), rhoD * (diffuseScale * w), 0.0}; }
    /// L Z' of Eq. (7): the triangle direction rotated by R_X(theta_s); Z' as printed, negative below.
    DirectionSample specular(const Vec3& tri, int k) const {
        const Vec3 d = lobe.toLocal(toOctant(tri, k));
        return {d, rhoS * (specularScale * d.z), 0.0};
    }
};

}  // namespace

std::uint32_t PaperEstimator::entries(const PhongMaterial& m) const {
    const std::uint32_t np = static_cast<std::uint32_t>(nPrime_);
    return 16 * (np + 1) + (m.hasSpecular() ? 8 * np : 0);
}

std::uint32_t PaperEstimator::spreadSetSize(const ShadingContext& ctx) const {
    return mode_ == SymmetricMode::Spread ? entries(*ctx.material) : 1;
}

void PaperEstimator::allDirections(const ShadingContext& ctx, SampleStream& samples, DirectionList& out) const {
    const PaperTerms terms(ctx, nPrime_, refined_);
    const bool specular = ctx.material->hasSpecular();
    for (int j = 0; j <= nPrime_; ++j) {  // Eq. (4) sums j = 0..N' as printed: N'+1 points
        const Point2 p = samples.get2D();
        const double w = paperWeight(p);
        const Vec3 tri = paperTriangleMap(p), quad = paperQuadrangleMap(p);
        for (int k = 0; k < 8; ++k) {
            out.push_back(terms.triangle(tri, w, k));
            out.push_back(terms.quadrangle(quad, w, k));
            if (specular && j >= 1) out.push_back(terms.specular(tri, k));  // Eq. (7) sums j = 1..N'
        }
    }
}

void PaperEstimator::sample(const ShadingContext& ctx, SampleStream& samples, DirectionList& out) const {
    if (ctx.branch && mode_ == SymmetricMode::Branch) {
        allDirections(ctx, samples, out);
        return;
    }
    // One of the K entries of allDirections, its weight times K: entries 0..8(N'+1)-1 are the triangle
    // directions of point j = e/8 in octant e mod 8, the next 8(N'+1) the quadrangle ones, the last 8N'
    // the specular ones of points 1..N'.
    const PaperTerms terms(ctx, nPrime_, refined_);
    const std::uint32_t K = entries(*ctx.material), tri = 8 * static_cast<std::uint32_t>(nPrime_ + 1);
    const std::uint32_t e = samples.patternEntry(K);
    const bool triangle = e < tri, quadrangle = !triangle && e < 2 * tri;
    const std::uint32_t rest = triangle ? e : quadrangle ? e - tri : e - 2 * tri;
    const int k = static_cast<int>(rest % 8);
    const std::uint32_t j = triangle || quadrangle ? rest / 8 : 1 + rest / 8;
    // Spread mode, first hit: point j of this round, shared by the round's samples.
    const Point2 p = samples.entryPoint(K, j, ctx.branch);
    DirectionSample s = triangle     ? terms.triangle(paperTriangleMap(p), paperWeight(p), k)
                        : quadrangle ? terms.quadrangle(paperQuadrangleMap(p), paperWeight(p), k)
                                     : terms.specular(paperTriangleMap(p), k);
    s.weight *= static_cast<double>(K);
    out.push_back(s);
}

// ---------------------------------------------------------------------------------------------------
// symmetric, symmetric-shifted

Point2 SymmetricEstimator::copyPoint(Point2 p, int k, PieceKind kind) const {
    if (!shifted_) return p;
    const double half = kind == PieceKind::Quadrangle ? 0.5 / 8.0 : 0.0;
    return {frac(p.u + ((3 * k) % 8) / 8.0 + half), frac(p.v + k / 8.0 + half)};
}

double SymmetricEstimator::diffuseSetDensity(const Vec3& wi) {
    return wi.z > 0 ? pieceDensity(inTriangles(wi) ? PieceKind::Triangle : PieceKind::Quadrangle, wi) : 0.0;
}

double SymmetricEstimator::lobeSetDensity(const ShadingContext& ctx, const LobeFrame& lobe, const Vec3& wi) {
    if (wi.z <= 0 || !ctx.material->hasSpecular()) return 0.0;
    const Vec3 face = lobe.toFace(wi);
    return face.z > 0 && inTriangles(face) ? lobeTriangleDensity(foldToOctant0(face), ctx.material->exponent) : 0.0;
}

double SymmetricEstimator::setDensity(const ShadingContext& ctx, const LobeFrame& lobe, const Vec3& wi) {
    return diffuseSetDensity(wi) + lobeSetDensity(ctx, lobe, wi);
}

std::uint32_t SymmetricEstimator::spreadSetSize(const ShadingContext& ctx) const {
    return mode_ == SymmetricMode::Spread ? static_cast<std::uint32_t>(nPrime_) * (ctx.material->hasSpecular() ? 24u : 16u) : 1u;
}

// Branch mode, first hit: the whole set, N' points x (16 + 8) directions, balance heuristic over both
// techniques. Shared work: the 8 copies of a piece share d_D (diffuse pieces: the same cos theta) or
// d_S (lobe triangles: the same folded face direction), so each is computed once per point.
void SymmetricEstimator::sampleSet(const ShadingContext& ctx, SampleStream& samples, DirectionList& out) const {
    const PhongMaterial& m = *ctx.material;
    const bool specular = m.hasSpecular();
    const LobeFrame lobe = LobeFrame::fromMirror(mirrorDirection(ctx.wo));
    const double scale = static_cast<double>(nPrime_);
    const auto push = [&](const Vec3& wi, double dD, double dS) {
        if (wi.z <= 0) return;  // a rotated direction below the surface carries no light (erratum 6)
        const Color f = evalPhong(m, ctx.wo, wi);
        if (isBlack(f)) return;
        const double d = scale * (dD + dS);
        out.push_back({wi, f * (wi.z / d), d});
    };
    for (int j = 0; j < nPrime_; ++j) {
        const Point2 p = samples.get2D();
        if (!shifted_) {
            // One point, three maps, then only sign flips and swaps: the paper's reuse by symmetry.
            const Vec3 tri = triangleMap(p), quad = quadrangleMap(p);
            const double dTri = pieceDensity(PieceKind::Triangle, tri), dQuad = pieceDensity(PieceKind::Quadrangle, quad);
            const Vec3 lobeDir = specular ? lobeTriangleMap(p, m.exponent) : Vec3();
            const double dLobe = specular ? lobeTriangleDensity(lobeDir, m.exponent) : 0.0;
            for (int k = 0; k < 8; ++k) {
                const Vec3 t = toOctant(tri, k), q = toOctant(quad, k);
                push(t, dTri, lobeSetDensity(ctx, lobe, t));
                push(q, dQuad, lobeSetDensity(ctx, lobe, q));
                if (specular) {
                    const Vec3 l = lobe.toLocal(toOctant(lobeDir, k));
                    push(l, diffuseSetDensity(l), dLobe);
                }
            }
            continue;
        }
        for (int k = 0; k < 8; ++k) {
            const Point2 pt = copyPoint(p, k, PieceKind::Triangle);
            const Vec3 t = toOctant(triangleMap(pt), k), q = toOctant(quadrangleMap(copyPoint(p, k, PieceKind::Quadrangle)), k);
            push(t, diffuseSetDensity(t), lobeSetDensity(ctx, lobe, t));
            push(q, diffuseSetDensity(q), lobeSetDensity(ctx, lobe, q));
            if (specular) {
                const Vec3 ld = lobeTriangleMap(pt, m.exponent);
                const Vec3 l = lobe.toLocal(toOctant(ld, k));
                push(l, diffuseSetDensity(l), lobeTriangleDensity(ld, m.exponent));
            }
        }
    }
}

void SymmetricEstimator::sample(const ShadingContext& ctx, SampleStream& samples, DirectionList& out) const {
    if (ctx.branch && mode_ == SymmetricMode::Branch) {
        sampleSet(ctx, samples, out);
        return;
    }
    const PhongMaterial& m = *ctx.material;
    const std::uint32_t pieces = m.hasSpecular() ? 24 : 16;
    // Spread mode at the first hit: the entries of N' points x P pieces over a round of camera samples,
    // the point shared by the round. Otherwise one point per sample and the N' = 1 pattern over pieces.
    const bool round = ctx.branch;
    const std::uint32_t entries = round ? static_cast<std::uint32_t>(nPrime_) * pieces : pieces;
    const std::uint32_t e = samples.patternEntry(entries);
    const std::uint32_t piece = e % pieces;
    const Point2 p = samples.entryPoint(entries, e / pieces, round);
    const int k = static_cast<int>(piece % 8);
    const LobeFrame lobe = LobeFrame::fromMirror(mirrorDirection(ctx.wo));
    Vec3 wi;
    if (piece < 8)
        wi = toOctant(triangleMap(copyPoint(p, k, PieceKind::Triangle)), k);
    else if (piece < 16)
        wi = toOctant(quadrangleMap(copyPoint(p, k, PieceKind::Quadrangle)), k);
    else
        wi = lobe.toLocal(toOctant(lobeTriangleMap(copyPoint(p, k, PieceKind::Triangle), m.exponent), k));
    if (wi.z <= 0) return;  // a rotated direction below the surface carries no light (erratum 6)
    const Color f = evalPhong(m, ctx.wo, wi);
    if (isBlack(f)) return;
    const double d = setDensity(ctx, lobe, wi) / pieces;
    out.push_back({wi, f * (wi.z / d), d});
}

double SymmetricEstimator::misPdf(const ShadingContext& ctx, const Vec3& wi) const {
    const LobeFrame lobe = LobeFrame::fromMirror(mirrorDirection(ctx.wo));
    const int pieces = ctx.material->hasSpecular() ? 24 : 16;
    const double scale = ctx.branch && mode_ == SymmetricMode::Branch ? static_cast<double>(nPrime_) : 1.0 / pieces;
    return scale * setDensity(ctx, lobe, wi);
}

namespace {
int checkedSymmetricN(const EstimatorOptions& options) {
    if (options.symmetricN < 1 || options.symmetricN > 4096)
        throw std::invalid_argument(fmt::format("--symmetric-n {} is out of range (1..4096)", options.symmetricN));
    return options.symmetricN;
}
}  // namespace

std::unique_ptr<Estimator> makePaperEstimator(const EstimatorOptions& o) {
    return std::make_unique<PaperEstimator>(checkedSymmetricN(o), o.paperRefined, o.symmetricMode);
}
std::unique_ptr<Estimator> makeSymmetricEstimator(const EstimatorOptions& o) {
    return std::make_unique<SymmetricEstimator>(checkedSymmetricN(o), false, o.symmetricMode);
}
std::unique_ptr<Estimator> makeSymmetricShiftedEstimator(const EstimatorOptions& o) {
    return std::make_unique<SymmetricEstimator>(checkedSymmetricN(o), true, o.symmetricMode);
}

}  // namespace symphong
