// The continuations of a path vertex under --splitting ears (PathTracer's members for it; the rest of the
// tracer is in path_tracer.cpp): how many a vertex gets from its learned factor (splitting/ears.h), which
// sample dimensions each reads, their MIS densities, and the records that the next epoch learns from
// (splitting/learning.h).
#include "estimators/basic.h"
#include "estimators/symmetric_mix.h"
#include "math/frame.h"
#include "render/path_tracer.h"
#include "scene/shading_normal.h"

#include <algorithm>

namespace symphong {

Color PathTracer::splitContinuations(const ShadingContext& sc, const Frame& frame, const Vec3& ng, const Vec3& p, std::size_t cell,
                                     bool shadowed, double q, double mis, int depth, std::uint64_t path, const Color& throughput,
                                     PathContext& pc) const {
    SampleStream& samples = pc.samples;
    // E[n] = q: floor(q), one more with probability q - floor(q). The first hit's q is a power of two already
    // (continuationFactor: firstHitBlock), so n = q there and its continuations are an aligned block of its
    // sample's block points (SampleStream::blockContinuation). A whole q draws nothing.
    // q in [kMinFactor, kMaxFactor]: truncation is floor (std::floor is a dozen instructions without SSE4.1).
    std::uint32_t n = static_cast<std::uint32_t>(q);
    const double whole = n;
    if (q > whole) {
        samples.setDimension(SampleDimensions::vertex(depth + 1, path) + SampleDimensions::kRoulette);
        n += samples.get1D() < q - whole ? 1u : 0u;
    }
    // Splitting (q >= 1, so n >= 1): the mean of the n continuations, unbiased for any n drawn apart from
    // their values, and without the variance that weights 1/q would add (n / q varies: mean^2 Var(n) / q^2,
    // which dwarfs the continuations' own variance under smooth light). Roulette (q < 1): 1/q.
    const double divisor = q >= 1 ? static_cast<double>(n) : q;
    const Vec3 origin = p + ng * epsilon_;
    DirectionList& dirs = pc.scratch.directions[static_cast<std::size_t>(depth)];
    Color L(0.0);
    std::uint64_t traced = 0;
    double sum = 0, squares = 0;  // of the continuations' luminances: the first hit's within-vertex variance
    const ears::Section section = depth == 0 ? ears::Section::FirstHit : ears::Section::Deeper;
    const bool record = depth == 0 ? firstHitRecords_ : records_;
    const bool orbit = depth == 0 && (n == 2 || n == 4 || n == 8) && settings_.splitting == SplittingMode::EarsOrbit;
    if (orbit) firstHitOrbit(sc, samples, n, pc.scratch.orbit);
    for (std::uint32_t j = 0; j < n; ++j) {
        const std::uint64_t own = j == 0 ? path : SampleDimensions::splitPath(path, depth, j);
        dirs.clear();
        if (orbit) {
            // --splitting ears-orbit: continuation j is copy j of the vertex's orbit, with phong's density (the
            // estimator's: settings refuse ears-orbit with another), so weighted and counted as an independent one.
            const Vec3& wi = pc.scratch.orbit[j];
            if (wi.z > 0) pushWeighted(sc, wi, SymmetricMixEstimator::directionDensity(sc, wi), dirs);
        } else if (depth == 0) {
            // At the first hit continuation j reads block point j of its sample (SampleStream::blockContinuation)
            // at the first-hit estimator's dimensions: the vertex's n continuations are a net, and so is
            // continuation j over the pixel's camera samples.
            SampleStream block = samples.blockContinuation(j);
            block.setDimension(SampleDimensions::firstHitEstimator(settings_.firstBounceStream));
            estimator_.sample(sc, block, dirs);
        } else {
            samples.setDimension(SampleDimensions::vertex(depth, own) + SampleDimensions::kEstimator);
            estimator_.sample(sc, samples, dirs);
        }
        const Color value =
            traceContinuation(dirs, frame, ng, origin, shadowed, mis, divisor, depth, own, throughput, record, cell, section, traced, pc);
        if (record) {
            const double y = pc.scratch.splitRecords.back().value;  // the luminance traceContinuation just recorded
            sum += y, squares += y * y;
        }
        L += value / divisor;
    }
    if (depth == 0 && record) {
        const double within = n > 1 ? std::max(0.0, squares - sum * sum / n) / (n - 1.0) : 0.0;
        pc.scratch.splitRecords.push_back({static_cast<std::uint32_t>(cell), within, n > 1 ? 1u : 0u, ears::Section::FirstHitVertex});
    }
    if (traced > 1) pc.stats.extraPaths += traced - 1;
    return L;
}

// One direction of a continuation, as traceContinuation's loop traces it (the same value, bit for bit: a sum
// that starts at 0).
inline Color PathTracer::traceDirection(const DirectionSample& s, const Frame& frame, const Vec3& ng, const Vec3& origin, bool shadowed,
                                        double mis, double divisor, int depth, std::uint64_t path, const Color& throughput,
                                        PathContext& pc) const {
    Color value(0.0);
    Vec3 wi;
    Color weight;
    if (!leavesSurface(s, frame, ng, shadowed, wi, weight)) return value;
    value += weight * radiance(origin, wi, depth + 1, path, s.misPdf * mis, throughput * weight / divisor, pc);
    return value;
}

// One continuation of a vertex under --splitting ears: the estimator's directions in `dirs` (one for every
// estimator but a set's), each traced with weight 1/divisor in its throughput and MIS density times `mis`,
// and, with `record`, reported as one record of its luminance and rays (splitting/learning.h Record); at
// the first hit also as a BrdfHit record of what its directions found of the lights (their weights times
// the emission met at the next vertex, PathScratch::bounceEmission).
inline Color PathTracer::traceContinuation(const DirectionList& dirs, const Frame& frame, const Vec3& ng, const Vec3& origin, bool shadowed,
                                           double mis, double divisor, int depth, std::uint64_t own, const Color& throughput, bool record,
                                           std::size_t cell, ears::Section section, std::uint64_t& traced, PathContext& pc) const {
    const std::uint64_t raysBefore = pc.stats.rays;
    const bool brdfRecord = record && section == ears::Section::FirstHit && lightSampling_;
    Color value(0.0), found(0.0);
    for (std::size_t k = 0; k < dirs.size(); ++k) {
        const DirectionSample& s = dirs[k];
        Vec3 wi;
        Color weight;
        if (!leavesSurface(s, frame, ng, shadowed, wi, weight)) continue;
        const std::uint64_t nextPath = dirs.size() > 1 ? k + 1 : own;  // a set's directions: paths of their own
        if (brdfRecord) pc.scratch.bounceEmission = Color(0.0);
        value += weight * radiance(origin, wi, depth + 1, nextPath, s.misPdf * mis, throughput * weight / divisor, pc);
        if (brdfRecord) found += weight * pc.scratch.bounceEmission;
        ++traced;
    }
    if (brdfRecord) {
        const double y = luminance(found);
        pc.scratch.splitRecords.push_back({static_cast<std::uint32_t>(cell), y, y > 0 ? 1u : 0u, ears::Section::BrdfHit});
    }
    if (record)
        pc.scratch.splitRecords.push_back({static_cast<std::uint32_t>(cell), luminance(value), pc.stats.rays - raysBefore, section});
    return value;
}

// A vertex after the first hit whose factor is q <= 1 (all but a few of them: splitContinuations' case n <= 1
// without its loop): roulette with survival q, then one continuation weighted 1/q.
Color PathTracer::rouletteContinuation(const ShadingContext& sc, const Frame& frame, const Vec3& ng, const Vec3& p, std::size_t cell,
                                       bool shadowed, double q, int depth, std::uint64_t path, const Color& throughput,
                                       PathContext& pc) const {
    SampleStream& samples = pc.samples;
    if (q < 1) {  // splitContinuations' n = floor(q + u) = 1 when u < q
        samples.setDimension(SampleDimensions::vertex(depth + 1, path) + SampleDimensions::kRoulette);
        if (samples.get1D() >= q) return Color(0.0);
    }
    DirectionList& dirs = pc.scratch.directions[static_cast<std::size_t>(depth)];
    dirs.clear();
    samples.setDimension(SampleDimensions::vertex(depth, path) + SampleDimensions::kEstimator);
    estimator_.sample(sc, samples, dirs);
    const Vec3 origin = p + ng * epsilon_;
    if (dirs.size() == 1) {  // every estimator but a set's: traceContinuation's one direction, inline
        const std::uint64_t raysBefore = pc.stats.rays;
        const Color value = traceDirection(dirs[0], frame, ng, origin, shadowed, q, q, depth, path, throughput, pc);
        if (records_)
            pc.scratch.splitRecords.push_back(
                {static_cast<std::uint32_t>(cell), luminance(value), pc.stats.rays - raysBefore, ears::Section::Deeper});
        return value / q;
    }
    std::uint64_t traced = 0;
    const Color value = traceContinuation(dirs, frame, ng, origin, shadowed, q, q, depth, path, throughput, records_, cell,
                                          ears::Section::Deeper, traced, pc);
    if (traced > 1) pc.stats.extraPaths += traced - 1;
    return value / q;
}

// A first hit whose factor is 1 (all of them in most cells under a sun or a small light): splitContinuations'
// n = 1 without its loop, its divisions by 1 and its variance sums: one continuation, block point 0 of its
// sample, and the vertex's FirstHitVertex record (no within-vertex variance) when the first hit records.
Color PathTracer::singleFirstHit(const ShadingContext& sc, const Frame& frame, const Vec3& ng, const Vec3& p, std::size_t cell,
                                 bool shadowed, std::uint64_t path, const Color& throughput, PathContext& pc) const {
    DirectionList& dirs = pc.scratch.directions[0];
    dirs.clear();
    SampleStream block = pc.samples.blockContinuation(0);
    block.setDimension(SampleDimensions::firstHitEstimator(settings_.firstBounceStream));
    estimator_.sample(sc, block, dirs);
    const Vec3 origin = p + ng * epsilon_;
    if (dirs.size() == 1 && !firstHitRecords_)
        return traceDirection(dirs[0], frame, ng, origin, shadowed, 1.0, 1.0, 0, path, throughput, pc);
    std::uint64_t traced = 0;
    const Color value = traceContinuation(dirs, frame, ng, origin, shadowed, 1.0, 1.0, 0, path, throughput, firstHitRecords_, cell,
                                          ears::Section::FirstHit, traced, pc);
    if (firstHitRecords_) pc.scratch.splitRecords.push_back({static_cast<std::uint32_t>(cell), 0.0, 0u, ears::Section::FirstHitVertex});
    if (traced > 1) pc.stats.extraPaths += traced - 1;
    return value;
}

// --splitting ears-orbit: a first hit's n continuations (n = 2, 4 or 8: firstHitBlock's powers of two) as one
// orbit of R = n symmetric copies of one point (estimators/symmetric_mix.h), its point and family offset the
// first-hit estimator's three dimensions of the camera sample (Sobol' dimensions 0-2 of one index under sobol).
void PathTracer::firstHitOrbit(const ShadingContext& sc, SampleStream& samples, std::uint32_t n, std::array<Vec3, 8>& copies) const {
    samples.setDimension(SampleDimensions::firstHitEstimator(settings_.firstBounceStream));
    const Vec3 u = samples.get3D();
    const int orbit = static_cast<int>(n);
    SymmetricMixEstimator::OrbitCopies orbitCopies(*sc.material, sc.wo, SymmetricMixEstimator::makeOrbit({u.x, u.y}, u.z, orbit), orbit);
    for (int j = 0; j < orbit; ++j) copies[static_cast<std::size_t>(j)] = orbitCopies(j);
}

}  // namespace symphong
