#include "estimators/symmetric.h"

#include <algorithm>
#include <cmath>

namespace symphong {

using namespace separation;

namespace {

Vec3 mirrorOf(const Vec3& wo) { return {-wo.x, -wo.y, wo.z}; }

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
    return kTwoPi / (n + 1.0) * (1.0 - 0.5 * (a + b));     // the conclusion's estimate
}

namespace {

/// The paper's three weighted directions from one point (u_j, v_j) and octant k, shared by the whole
/// estimate and by the one-direction form used at deeper bounces.
struct PaperTerms {
    Color rhoD, rhoS;       ///< the paper's rho_d (= ours / pi) and rho_s (= ours (n+2)/(2 pi))
    double diffuseScale;    ///< Eq. (4): pi / (48 N')
    double specularScale;   ///< Eq. (7): 2 pi (1 - (sqrt3/3)^(n+1)) / ((n+1) N), N = 8N'
    LobeFrame lobe;

    PaperTerms(const ShadingContext& ctx, int nPrime, bool refined)
        : rhoD(ctx.material->rhoD * kInvPi),
          rhoS(ctx.material->rhoS * ((ctx.material->exponent + 2.0) / kTwoPi)),
          diffuseScale(kPi / (48.0 * nPrime)),
          specularScale(PaperEstimator::lobeNormalisation(ctx.material->exponent, refined) / (8.0 * nPrime)),
          lobe(LobeFrame::fromMirror(mirrorOf(ctx.wo))) {}

    // Each takes the point's map image in octant 0 (computed once per point) and its weight w(u,v).
    /// (1/2) L_tri w(u,v) of Eq. (4), from paperTriangleMap.
    DirectionSample triangle(const Vec3& tri, double w, int k) const {
        return {toOctant(tri, k), rhoD * (diffuseScale * 0.5 * w), 0.0};
    }
    /// L_quad w(u,v) of Eq. (4), from paperQuadrangleMap.
    DirectionSample quadrangle(const Vec3& quad, double w, int k) const {
        return {toOctant(quad, k), rhoD * (diffuseScale * w), 0.0};
    }
    /// L Z' of Eq. (7): the triangle direction rotated by R_X(theta_s); Z' as printed, negative below.
    DirectionSample specular(const Vec3& tri, int k) const {
        const Vec3 d = lobe.toLocal(toOctant(tri, k));
        return {d, rhoS * (specularScale * d.z), 0.0};
    }
};

}  // namespace

void PaperEstimator::allDirections(const ShadingContext& ctx, Rng& rng, std::vector<DirectionSample>& out) const {
    const PaperTerms terms(ctx, nPrime_, refined_);
    const bool specular = ctx.material->hasSpecular();
    for (int j = 0; j <= nPrime_; ++j) {  // Eq. (4) sums j = 0..N' as printed: N'+1 points
        const Point2 p = rng.uniform2();
        const double w = paperWeight(p);
        const Vec3 tri = paperTriangleMap(p), quad = paperQuadrangleMap(p);
        for (int k = 0; k < 8; ++k) {
            out.push_back(terms.triangle(tri, w, k));
            out.push_back(terms.quadrangle(quad, w, k));
            if (specular && j >= 1) out.push_back(terms.specular(tri, k));  // Eq. (7) sums j = 1..N'
        }
    }
}

void PaperEstimator::sample(const ShadingContext& ctx, Rng& rng, std::vector<DirectionSample>& out) const {
    if (ctx.branch) {
        allDirections(ctx, rng, out);
        return;
    }
    // One of the K = 16(N'+1) + 8N' entries of allDirections, uniformly, its weight times K. The points
    // are independent, so an entry's point is a fresh one: draw only the chosen direction.
    const PaperTerms terms(ctx, nPrime_, refined_);
    const double np = nPrime_;
    const double tri = 8.0 * (np + 1.0), spec = ctx.material->hasSpecular() ? 8.0 * np : 0.0, total = 2.0 * tri + spec;
    const double pick = rng.uniform() * total;
    const int k = std::min(7, static_cast<int>(rng.uniform() * 8.0));
    const Point2 p = rng.uniform2();
    DirectionSample s = pick < tri         ? terms.triangle(paperTriangleMap(p), paperWeight(p), k)
                        : pick < 2.0 * tri ? terms.quadrangle(paperQuadrangleMap(p), paperWeight(p), k)
                                           : terms.specular(paperTriangleMap(p), k);
    s.weight *= total;
    out.push_back(s);
}

// ---------------------------------------------------------------------------------------------------
// symmetric, symmetric-shifted

Point2 SymmetricEstimator::copyPoint(Point2 p, int k, PieceKind kind) const {
    if (!shifted_) return p;
    const double half = kind == PieceKind::Quadrangle ? 0.5 / 8.0 : 0.0;
    return {frac(p.u + ((3 * k) % 8) / 8.0 + half), frac(p.v + k / 8.0 + half)};
}

double SymmetricEstimator::setDensity(const ShadingContext& ctx, const LobeFrame& lobe, const Vec3& wi) {
    if (wi.z <= 0) return 0.0;
    double d = pieceDensity(inTriangles(wi) ? PieceKind::Triangle : PieceKind::Quadrangle, wi);
    if (ctx.material->hasSpecular()) {
        const Vec3 face = lobe.toFace(wi);
        if (face.z > 0 && inTriangles(face)) d += lobeTriangleDensity(foldToOctant0(face), ctx.material->exponent);
    }
    return d;
}

void SymmetricEstimator::sample(const ShadingContext& ctx, Rng& rng, std::vector<DirectionSample>& out) const {
    const PhongMaterial& m = *ctx.material;
    const bool specular = m.hasSpecular();
    const LobeFrame lobe = LobeFrame::fromMirror(mirrorOf(ctx.wo));
    const int pieces = specular ? 24 : 16;
    const double scale = ctx.branch ? static_cast<double>(nPrime_) : 1.0 / pieces;
    const auto push = [&](const Vec3& wi) {
        if (wi.z <= 0) return;  // a rotated direction below the surface carries no light (erratum 6)
        const Color f = evalPhong(m, ctx.wo, wi);
        if (isBlack(f)) return;
        const double d = scale * setDensity(ctx, lobe, wi);
        out.push_back({wi, f * (wi.z / d), d});
    };
    if (!ctx.branch) {
        const int piece = std::min(pieces - 1, static_cast<int>(rng.uniform() * pieces));
        const Point2 p = rng.uniform2();
        const int k = piece % 8;
        if (piece < 8) push(toOctant(triangleMap(p), k));
        else if (piece < 16) push(toOctant(quadrangleMap(p), k));
        else push(lobe.toLocal(toOctant(lobeTriangleMap(p, m.exponent), k)));
        return;
    }
    for (int j = 0; j < nPrime_; ++j) {
        const Point2 p = rng.uniform2();
        if (!shifted_) {
            // One point, three maps, then only sign flips and swaps: the paper's reuse by symmetry.
            const Vec3 tri = triangleMap(p), quad = quadrangleMap(p);
            const Vec3 lobeDir = specular ? lobeTriangleMap(p, m.exponent) : Vec3();
            for (int k = 0; k < 8; ++k) {
                push(toOctant(tri, k));
                push(toOctant(quad, k));
                if (specular) push(lobe.toLocal(toOctant(lobeDir, k)));
            }
            continue;
        }
        for (int k = 0; k < 8; ++k) {
            const Point2 pt = copyPoint(p, k, PieceKind::Triangle);
            push(toOctant(triangleMap(pt), k));
            push(toOctant(quadrangleMap(copyPoint(p, k, PieceKind::Quadrangle)), k));
            if (specular) push(lobe.toLocal(toOctant(lobeTriangleMap(pt, m.exponent), k)));
        }
    }
}

double SymmetricEstimator::misPdf(const ShadingContext& ctx, const Vec3& wi) const {
    const LobeFrame lobe = LobeFrame::fromMirror(mirrorOf(ctx.wo));
    const int pieces = ctx.material->hasSpecular() ? 24 : 16;
    const double scale = ctx.branch ? static_cast<double>(nPrime_) : 1.0 / pieces;
    return scale * setDensity(ctx, lobe, wi);
}

}  // namespace symphong
