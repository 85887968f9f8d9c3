// estimators/ — the reflected-radiance estimators: given a shading point (the outgoing direction and
// its Phong material, in the local frame), each returns one or several weighted directions whose
// weighted sum of incoming radiance estimates  L_r(wo) = integral f(wo,wi) L_in(wi) cos(theta_i) dwi.
// The path tracer (render/) is written against this interface only, so strategies can be compared with
// everything else held fixed. Estimators own no geometry and trace no rays.
#pragma once

#include "materials/phong.h"
#include "math/vec3.h"
#include "sampling/sampler.h"
#include "util/cache_line.h"

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace symphong {

struct ShadingContext {
    Vec3 wo;  ///< outgoing direction, local frame (wo.z > 0)
    const PhongMaterial* material = nullptr;
    int depth = 0;  ///< 0 at the first surface seen from the camera
    /// Whether the estimator may return several directions (the path tracer allows it at the first
    /// hit only, so paths never branch exponentially); otherwise it returns at most one.
    bool branch = false;
};

/// How the symmetric estimators use their set of P pieces (16 diffuse + 8 lobe) at the first hit.
enum class SymmetricMode {
    Branch,  ///< one camera sample traces the whole set: P paths (x N') from its first hit
    Spread,  ///< the set is spread over consecutive camera samples of a pixel, one piece each
};

struct DirectionSample {
    Vec3 wi;        ///< incoming-light direction, local frame
    Color weight;   ///< f(wo,wi) cos(theta_i) / (K p(wi)) for the K directions of one call: L_r ~= sum weight * L_in
    double misPdf;  ///< K p(wi): the density of the call's direction set, as multiple importance sampling needs it
};

/// A direction drawn ahead of its shading point (Estimator::drawAhead): the part of sample()'s single direction
/// that depends only on the material and the call's first 2D value, computed before the outgoing direction is
/// known. `local` is in the shading frame, or, where `aroundMirror`, in a frame around wo's mirror direction.
struct DirectionDraw {
    Vec3 local;
    bool aroundMirror = false;
};

/// The directions of a call: a buffer alone on its cache lines, since the path tracer's threads each
/// write their own on every sample (util/cache_line.h).
using DirectionList = CacheLineVector<DirectionSample>;

class Estimator {
public:
    virtual ~Estimator() = default;

    virtual std::string_view name() const = 0;

    /// Appends this strategy's directions for one shading point to `out` (which it does not clear).
    /// A direction below the surface may be omitted (for an unbiased estimator it carries zero weight;
    /// `paper` returns its below-horizon directions with the weights its formula gives them). With
    /// ctx.branch false, at most one direction. Every random decision draws from `samples`, starting at
    /// the dimension it is positioned at; with ctx.branch false an estimator uses at most five
    /// dimensions, with ctx.branch true as many as it needs (the caller reserves a block).
    virtual void sample(const ShadingContext& ctx, SampleStream& samples, DirectionList& out) const = 0;

    /// The misPdf that sample() would attach to direction wi at this point (0 where it never samples).
    virtual double misPdf(const ShadingContext& ctx, const Vec3& wi) const = 0;

    /// Whether the path tracer may combine this estimator with light sampling by MIS. An estimator
    /// without a density (the paper's, as printed) must account for all reflected light itself.
    virtual bool combinesWithLightSampling() const { return true; }

    /// Whether a call with ctx.branch returns a whole set of directions (the symmetric estimators), so
    /// that one call is one estimate; otherwise a call returns at most one direction.
    virtual bool returnsSets() const { return false; }
    /// The most directions that one call with ctx.branch returns: a whole set where returnsSets(), else 1 (the
    /// wavefront tracer sizes its batch by it, render/wavefront.cpp).
    virtual std::uint32_t largestSet() const { return 1; }

    /// For estimators whose set is spread over camera samples: the number of samples that make up one
    /// whole set at this shading point (its entries); 1 for the others.
    virtual std::uint32_t spreadSetSize(const ShadingContext&) const { return 1; }

    /// Whether drawAhead and sampleDrawn are this estimator's for a call with ctx.branch = `branch`: its single
    /// direction drawn from the material and the first 2D value that sample() reads, before the shading point's
    /// outgoing direction is known (the wavefront tracer draws a depth's directions together,
    /// render/wavefront.cpp). An estimator whose first hit returns a set draws ahead at deeper vertices only.
    virtual bool drawsAhead(bool /*branch*/) const { return false; }
    /// Draws ahead for the n points with materials[i] (skipping a null one) from the 2D values (us[i], vs[i]).
    virtual void drawAhead(const PhongMaterial* const*, const double*, const double*, std::size_t, DirectionDraw*) const {}
    /// sample() for a point (ctx.branch false, or an estimator that returns one direction either way) whose
    /// direction was drawn ahead from the value sample() would read first: the same directions, the same bits;
    /// it reads nothing from a stream.
    virtual void sampleDrawn(const ShadingContext&, const DirectionDraw&, DirectionList&) const {}

    /// The sampler this estimator is defined with, overriding the one asked for (`stratified` is cosine
    /// sampling under the stratified sampler); empty for the others.
    virtual std::string_view requiredSampler() const { return {}; }
};

/// Settings that only some estimators read.
struct EstimatorOptions {
    int symmetricN = 1;                                   ///< N': (u,v) points per piece for `paper`, `symmetric`, `symmetric-shifted`
    bool paperRefined = false;                            ///< `paper`: the conclusion's finer lobe normalisation instead of Eq. (6)'s
    SymmetricMode symmetricMode = SymmetricMode::Branch;  ///< `paper`, `symmetric*`: branch or spread
    int symmetricOrbit = 2;                               ///< `symmetric-mix`: copies of one point used together (1, 2, 4 or 8)
};

/// "branch" or "spread".
std::string_view symmetricModeName(SymmetricMode mode);
/// Parses "branch" or "spread"; throws std::invalid_argument otherwise.
SymmetricMode parseSymmetricMode(std::string_view name);

/// Names accepted by makeEstimator, in the order --help lists them.
const std::vector<std::string>& estimatorNames();

/// One line per estimator for --help.
std::string estimatorHelp();

/// Whether the named estimator has the branch and spread modes (`paper`, `symmetric`, `symmetric-shifted`, `symmetric-mix`).
bool hasSymmetricModes(std::string_view name);

/// The sampler a render or furnace with this estimator uses: the estimator's own, else the one asked for.
std::string effectiveSampler(const Estimator& estimator, const std::string& requested);

/// Creates an estimator by name; throws std::invalid_argument listing the valid names otherwise, or
/// naming an option that is out of range.
std::unique_ptr<Estimator> makeEstimator(std::string_view name, const EstimatorOptions& options = {});

}  // namespace symphong
