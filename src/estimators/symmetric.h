// estimators/symmetric.h — the symmetric-sampling estimators of the Uniform Separation: the paper's
// Eq. (8) exactly as printed (`paper`), our corrected unbiased version (`symmetric`) and its
// decorrelated variant (`symmetric-shifted`). docs/estimators.md derives each weight.
#pragma once

#include "estimators/estimator.h"
#include "sampling/separation.h"

namespace symphong {

/// Factories of the table in estimators/registry.cpp: they read N' (--symmetric-n, 1..4096), the mode
/// and, for `paper`, the refined normalisation.
std::unique_ptr<Estimator> makePaperEstimator(const EstimatorOptions& options);
std::unique_ptr<Estimator> makeSymmetricEstimator(const EstimatorOptions& options);
std::unique_ptr<Estimator> makeSymmetricShiftedEstimator(const EstimatorOptions& options);

/// `paper`: Eq. (4) + Eq. (7) = Eq. (8), formula for formula. The paper's rho_d is our rho_d / pi and its
/// rho_s our rho_s (n+2)/(2 pi), so a render differs from ours by the estimator alone. N'+1 points
/// (u_j,v_j), j = 0..N', feed Eq. (4)'s sum as printed; j = 1..N' feed Eq. (7). Each point gives 8 triangle
/// directions (paper's triangle map), 8 "quadrangle" directions (paper's map, which lands in the wrong
/// place) and 8 specular directions (the triangle directions rotated by R_X(theta_s)), weighted:
///   triangle   rho_d/pi * pi/(48 N') * 1/2 * w(u_j,v_j)          (Eq. 4, p_T = 1/24 as a weight)
///   quadrangle rho_d/pi * pi/(48 N') * w(u_j,v_j)                (Eq. 4, p_Q = 1/12)
///   specular   rho_s^paper * 2 pi/(8 N' (n+1)) * (1 - (sqrt3/3)^(n+1)) * Z'   (Eq. 7; Z' may be < 0)
/// It is biased (errata 2-6). Without a density it cannot be combined with light sampling.
/// Without a whole set (deeper bounces, or spread mode) one of its K = 16(N'+1) + 8N' entries is kept,
/// chosen by the spread pattern of the sample index, its weight times K; in spread mode at the first hit
/// the entries' points are shared by the samples of a round, so a round of K samples is one whole set.
class PaperEstimator final : public Estimator {
public:
    PaperEstimator(int nPrime, bool refined, SymmetricMode mode = SymmetricMode::Branch)
        : nPrime_(nPrime), refined_(refined), mode_(mode) {}
    std::string_view name() const override { return "paper"; }
    void sample(const ShadingContext& ctx, SampleStream& samples, DirectionList& out) const override;
    double misPdf(const ShadingContext&, const Vec3&) const override { return 0.0; }
    bool combinesWithLightSampling() const override { return false; }
    bool returnsSets() const override { return mode_ == SymmetricMode::Branch; }
    std::uint32_t largestSet() const override {
        return returnsSets() ? 16 * static_cast<std::uint32_t>(nPrime_ + 1) + 8 * static_cast<std::uint32_t>(nPrime_) : 1;
    }
    std::uint32_t spreadSetSize(const ShadingContext& ctx) const override;

    /// The specular normalisation: Eq. (6)'s 2 pi (1 - (sqrt3/3)^(n+1)) / (n+1), or the conclusion's
    /// 2 pi/(n+1) (1 - ((sqrt3/3)^(n+1) + (sqrt2/2)^(n+1)) / 2) when refined.
    static double lobeNormalisation(double n, bool refined);
    /// Every direction of one full estimate (all weights, including negative specular ones below the
    /// horizon), as printed; sample() keeps those a render can use.
    void allDirections(const ShadingContext& ctx, SampleStream& samples, DirectionList& out) const;
    /// Number of entries of one whole estimate: 16 (N'+1) + 8 N' (no specular entries without a lobe).
    std::uint32_t entries(const PhongMaterial& m) const;

private:
    int nPrime_;
    bool refined_;
    SymmetricMode mode_;
};

/// `symmetric` and `symmetric-shifted`: the corrected estimator. For each of N' points (u,v):
///  - 16 diffuse-part directions, one in each piece T_i, Q_i, from the exact projected-solid-angle maps
///    (the same (u,v) moved into each octant by the signed permutations, or shifted per copy), and
///  - when the material has a specular lobe, 8 directions in the triangles rotated onto the mirror
///    direction (lobe-shaped map of T_0, the same (u,v), symmetry, R_X(theta_s)).
/// Both techniques are combined by the balance heuristic: every direction is weighted by
///   f(wo,wi) cos(theta_i) / d(wi),   d = N' (d_D + d_S),
/// d_D the 16 diffuse pieces' density at wi (cos/Phi_T or cos/Phi_Q) and d_S the rotated triangles'
/// (zero outside them). d_D covers the whole hemisphere, so the lobe outside the rotated face is still
/// estimated, and the estimator is unbiased; below-horizon directions carry f = 0. d is the misPdf.
/// Shifted: copy i uses (frac(u + p(i)/8), frac(v + i/8)), p(i) = 3i mod 8, quadrangles a further half
/// stratum (+1/16, +1/16), so the 8 copies form a Latin hypercube instead of sharing one elevation.
/// One direction instead of a set (deeper bounces, and every bounce in spread mode): entry e of the
/// N' P entries (P = 16, or 24 with a lobe) chosen by the spread pattern of the sample index (a whole
/// round of N' P camera samples takes every entry once, each sample's entry uniform on its own), piece
/// e mod P, one direction in it; weight f cos / (d_1 / P), d_1 the N' = 1 density. In spread mode at the
/// first hit the round's samples share the point (u,v) of entry e / P (shifted: its copies), drawn once
/// per round from the sampler, so a round is the branch-mode set spread over camera samples;
/// docs/estimators.md derives why each sample is unbiased on its own.
class SymmetricEstimator final : public Estimator {
public:
    SymmetricEstimator(int nPrime, bool shifted, SymmetricMode mode = SymmetricMode::Branch)
        : nPrime_(nPrime), shifted_(shifted), mode_(mode) {}
    std::string_view name() const override { return shifted_ ? "symmetric-shifted" : "symmetric"; }
    void sample(const ShadingContext& ctx, SampleStream& samples, DirectionList& out) const override;
    double misPdf(const ShadingContext& ctx, const Vec3& wi) const override;
    bool returnsSets() const override { return mode_ == SymmetricMode::Branch; }
    std::uint32_t largestSet() const override { return returnsSets() ? 24 * static_cast<std::uint32_t>(nPrime_) : 1; }
    std::uint32_t spreadSetSize(const ShadingContext& ctx) const override;

    /// d_D + d_S at wi for one point per piece (N' = 1).
    static double setDensity(const ShadingContext& ctx, const separation::LobeFrame& lobe, const Vec3& wi);
    /// d_D at wi: the density of the diffuse piece that holds wi (cos/Phi_T or cos/Phi_Q).
    static double diffuseSetDensity(const Vec3& wi);
    /// d_S at wi: the rotated lobe triangles' density (0 outside them or without a lobe).
    static double lobeSetDensity(const ShadingContext& ctx, const separation::LobeFrame& lobe, const Vec3& wi);
    /// The (u,v) used by copy `k` of a piece kind, from the shared point p.
    Point2 copyPoint(Point2 p, int k, separation::PieceKind kind) const;

private:
    void sampleSet(const ShadingContext& ctx, SampleStream& samples, DirectionList& out) const;

    int nPrime_;
    bool shifted_;
    SymmetricMode mode_;
};

}  // namespace symphong
