// render/ — turning a scene into an image. Owns the path tracer (next-event estimation + multiple
// importance sampling with whatever estimator was chosen, Russian roulette), the camera model, and the
// parallel, reproducible tile loop. It asks accel/ for ray queries, estimators/ for directions and
// lights/ for emitters (one direct-lighting routine for every kind), and never looks inside any of them.
#pragma once

#include "accel/accel.h"
#include "estimators/estimator.h"
#include "estimators/symmetric_mix.h"
#include "lights/emitters.h"
#include "math/frame.h"
#include "render/direct_light.h"
#include "render/wavefront.h"
#include "scene/scene.h"
#include "scene/shading_normal.h"
#include "scene/surface.h"
#include "splitting/learning.h"
#include "util/cache_line.h"

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

namespace symphong {

/// TraceSettings::tracer: automatic, or one tracer by name.
enum class TracerChoice { Automatic, Recursive, Wavefront };

struct TraceSettings {
    int maxDepth = 16;      ///< most scattering events on a path; 0 shows emitters only
    int rrDepth = 3;        ///< Russian roulette from this depth on
    bool nextEvent = true;  ///< light sampling (next-event estimation) combined by MIS
    /// First-hit splitting: the estimator is called this many times at the first hit (sub-samples j of
    /// k of the camera sample, SampleStream::split), each direction weighted 1/k and continued as a path
    /// of its own; 1: no splitting (and so is any value below 1).
    int firstHitSplit = 1;
    /// Which block of sampler dimensions the first hit's estimator reads: 0 is the render's own; another
    /// value gives the first-bounce directions numbers independent of the render's while every other
    /// decision of the path keeps its numbers (the variance budget: the spread of renders that differ
    /// only in this value is the part of the variance that comes from the first-bounce directions).
    std::uint32_t firstBounceStream = 0;
    /// Whether the first hit's first pair of estimator dimensions and the pixel position form one 4D
    /// pattern (Sampler::value2DJoint) instead of two independently matched pairs.
    bool jointFirstBounce = false;
    /// Where a normal or bump map bent the shading normal, multiply the BRDF by the shadowing term of
    /// Chiang, Li and Burley 2019 (scene/shading_normal.h bumpShadowing), as Blender Cycles does.
    bool bumpShadowing = false;
    /// How many continuations a vertex gets: one (Russian roulette by throughput, firstHitSplit at the
    /// first hit) or EARS's learned factor at every vertex (splitting/ears.h; replaces both).
    SplittingMode splitting = SplittingMode::None;
    /// --splitting ears: a learned roulette factor no harsher than plain roulette's (ears::flooredRoulette).
    /// The renderer sets it when the render's sampler is not one of independent values.
    bool earsRouletteFloor = false;
    /// Which tracer takes the camera samples where both can (PathTracer::tracesAsWavefront): the same paths and
    /// radiances bit for bit either way, so a choice of speed only. Automatic: the wavefront where the sampler's
    /// vector lanes run (sampling/sobol_lanes.h), the faster there; the recursive tracer elsewhere, where the
    /// wavefront is the slower (docs/performance.md "The second tracer"). Benchmarks and tests name one.
    TracerChoice tracer = TracerChoice::Automatic;
};

struct TraceStats {
    std::uint64_t rays = 0;        ///< closest-hit and shadow queries
    std::uint64_t extraPaths = 0;  ///< rays beyond the first that a branching vertex traces (each starts a path of its own)
    std::uint64_t badSamples = 0;  ///< non-finite path contributions, discarded (counted, never written)
};

/// Where each random decision of a camera sample reads the sampler: dimension numbers, fixed for a
/// given depth and path, so no two decisions share a value and every sampler sees the same layout.
/// Path 0 is the camera sample's own path; a set estimator's branches at the first hit are paths 1..K.
struct SampleDimensions {
    static constexpr std::uint64_t kPixel = 0;  ///< pair: position inside the pixel
    static constexpr std::uint64_t kFirstBounce = 2;
    static constexpr std::uint64_t kPerBounce = 8;                   ///< dimensions of one path vertex:
    static constexpr std::uint64_t kLight = 0;                       ///<   pair: emitter choice (folded into u) and point
    static constexpr std::uint64_t kEstimator = 2;                   ///<   up to 5: the estimator's one direction
    static constexpr std::uint64_t kRoulette = 7;                    ///<   Russian roulette on arriving at this vertex
    static constexpr std::uint64_t kPathStride = 1u << 14;           ///< > kPerBounce x (max depth 1024 + 1)
    static constexpr std::uint64_t kFirstHitEstimator = 1ull << 40;  ///< the first hit's estimator: a block of any size
    static constexpr std::uint64_t kFirstHitStreamStride =
        1ull << 32;  ///< TraceSettings::firstBounceStream s reads from kFirstHitEstimator + s x this
    static constexpr std::uint64_t kFirstSplitPath = 1u << 20;  ///< --splitting ears's continuation paths: from here on
    static constexpr std::uint64_t kPathCount = 1u << 26;       ///< paths x kPathStride stay below kFirstHitEstimator
    /// First dimension of the vertex at `depth` of path `path`.
    static constexpr std::uint64_t vertex(int depth, std::uint64_t path) {
        return kFirstBounce + path * kPathStride + static_cast<std::uint64_t>(depth) * kPerBounce;
    }
    /// The first hit's estimator: stream s (TraceSettings::firstBounceStream). A vertex split by
    /// --splitting ears reads continuation j there as block point j of its sample (SampleStream::blockContinuation).
    static constexpr std::uint64_t firstHitEstimator(std::uint32_t stream) { return kFirstHitEstimator + stream * kFirstHitStreamStride; }
    /// --splitting ears: the path that continuation j >= 1 of the vertex at `depth` of `path` starts (its
    /// own dimensions from that vertex on; continuation 0 continues `path`), hashed into
    /// [kFirstSplitPath, kPathCount), clear of the paths 1..K of a set's branches.
    static constexpr std::uint64_t splitPath(std::uint64_t path, int depth, std::uint32_t j) {
        return kFirstSplitPath + mixSeed(mixSeed(path, static_cast<std::uint64_t>(depth)), j) % (kPathCount - kFirstSplitPath);
    }
};

/// The continuing rays of a branching vertex (a set estimator's directions), traced together.
struct RayBundle {
    struct Ray {       ///< what ray i continues with; its world direction is dirs[i]
        Color weight;  ///< the estimator's weight
        Color next;    ///< throughput that steers roulette further on
        double misPdf;
        double survive;      ///< Russian roulette survival probability (already passed)
        std::uint64_t path;  ///< the branch's path number (its dimensions)
    };
    // Written by one thread on every branching vertex: each buffer alone on its cache lines.
    CacheLineVector<Ray> rays;
    CacheLineVector<Vec3> dirs;  ///< world directions, contiguous for Accel::intersectBundle
    CacheLineVector<Hit> hits;
    CacheLineArray<bool> found;  ///< not std::vector<bool>, which has no bool* to hand to Accel
    std::size_t capacity = 0;    ///< length of `found`
};

/// Per-thread working memory of the path tracer.
struct PathScratch {
    CacheLineVector<DirectionList> directions;  ///< one buffer per depth (each alone on its cache lines: util/cache_line.h)
    CacheLineVector<RayBundle> bundles;         ///< one per depth
    CacheLineVector<PhongMaterial> materials;   ///< one per depth: a textured material's parameters at its vertex
    std::vector<ears::Record> splitRecords;     ///< --splitting ears: the continuations traced since the caller last took them
    std::array<Vec3, 8> orbit;                  ///< --splitting ears-orbit: the first hit's copies (PathTracer::firstHitOrbit)
    std::vector<WavefrontBatch> wavefront;      ///< the wavefront tracer's batch: one, allocated by its first call
    /// The emission (unweighted) that a ray from a first hit met at the next vertex, when light sampling could
    /// have found it too (else 0): set by that vertex, for --splitting ears's BrdfHit records.
    Color bounceEmission{0.0};
};

class PathTracer {
public:
    /// `learning`: with settings.splitting Ears, the factors of the epoch being rendered (their grid and
    /// factors are read, never written; continuations are reported in PathScratch::splitRecords unless
    /// `records` is false: in the render's last epoch, whose records no later epoch would learn from).
    PathTracer(const Scene& scene, const Accel& accel, const Estimator& estimator, TraceSettings settings,
               const ears::Learning* learning = nullptr, bool records = true);

    /// Radiance arriving at the camera along o + t d, every decision drawn from `samples` (one camera
    /// sample's stream) at the dimensions of SampleDimensions.
    Color cameraRadiance(const Vec3& o, const Vec3& d, SampleStream& samples, TraceStats& stats, PathScratch& scratch) const;
    /// The most camera rays cameraRadiances takes: one Embree packet (the recursive tracer), or a wavefront's
    /// batch (tracesAsWavefront(), its camera rays traced as packets of kCameraPacket): as many camera samples as
    /// leave a slot for each of their first hits' continuations (WavefrontBatch::kSize / firstHitBranches()).
    static constexpr std::size_t kCameraPacket = 16;
    std::size_t cameraBatch() const { return wavefront_ ? WavefrontBatch::kSize / firstHitBranches_ : kCameraPacket; }
    /// cameraRadiance of n <= cameraBatch() camera rays o + t dirs[k] from one origin (a pinhole camera's:
    /// neighbouring samples of a tile, render/renderer.cpp CameraPackets), out[k] from streams[k]: their
    /// first hits found as one coherent packet (Accel::intersectBundle), then each path traced on its own,
    /// in order. The same radiances as n calls
    /// of cameraRadiance (the packet's hits are the single rays', bit for bit on this machine: the golden
    /// images and EXRs compared with `cmp`), with Embree's traversal of the camera rays shared.
    /// With tracesAsWavefront(), the paths go depth by depth instead (render/wavefront.cpp): the same paths and
    /// radiances, bit for bit.
    void cameraRadiances(const Vec3& o, const Vec3* dirs, std::size_t n, SampleStream* streams, Color* out, TraceStats& stats,
                         PathScratch& scratch) const;

    /// Whether cameraRadiances takes its paths depth by depth (TraceSettings::tracer: named, or automatic where the
    /// sampler's lanes run and a first hit has at most kAutomaticWavefrontBranches continuations): without
    /// --splitting ears or a joint first-bounce pattern, and with at most WavefrontBatch::kSize continuations at a
    /// first hit (firstHitBranches()).
    bool tracesAsWavefront() const { return wavefront_; }
    /// The most continuations a first hit has: --split k's k calls of the estimator, each a whole set of its
    /// (Estimator::largestSet) where it returns sets.
    std::size_t firstHitBranches() const { return firstHitBranches_; }
    /// The most first-hit continuations with which the automatic choice takes the wavefront: above it (`symmetric`'s
    /// sets of 24, `paper`'s of 40) a batch holds at most ten camera samples and the wavefront was no faster than
    /// the recursive tracer (docs/performance.md "A branching first hit in the wavefront").
    static constexpr std::size_t kAutomaticWavefrontBranches = 16;

    const Scene& scene() const { return scene_; }
    /// --splitting ears: whether continuations are reported from now on: the deeper vertices' (a tracer kept
    /// from epoch to epoch: off in the render's last; off in the probe, whose deeper factors are never used)
    /// and the first hit's (off once its factors hold for good, splitting/learning.h kProbeSamples). Not while
    /// a render uses the tracer.
    void setRecords(bool deeper, bool firstHit) { records_ = deeper, firstHitRecords_ = firstHit; }
    /// --splitting ears: whether EARS rests (ears::Learning::resting): no vertex then looks up or records a
    /// factor; each takes one continuation, with roulette by its throughput from the roulette depth on
    /// (restingFactor: what learned factors that split nothing floor to). Not while a render uses the tracer.
    void setResting(bool resting) { resting_ = resting; }
    double epsilon() const { return epsilon_; }

private:
    /// Sizes the scratch's per-depth buffers for this tracer's maximum depth (once per thread).
    void prepare(PathScratch& scratch) const;
    struct PathContext {
        SampleStream& samples;
        TraceStats& stats;
        PathScratch& scratch;
    };
    Color radiance(const Vec3& o, const Vec3& d, int depth, std::uint64_t path, double prevMisPdf, const Color& throughput,
                   PathContext& pc) const;
    /// The sample dimension of the estimator's first value at a vertex of this depth (the first hit's own stream).
    std::uint64_t estimatorDimension(int depth, std::uint64_t path) const;
    /// The sampler's values that the batch's live paths at a surface read at `depth` (the light sample, the
    /// estimator's pair, the roulette), computed for all of them at once in the lanes of sobol_lanes.h and
    /// read through their streams (SampleStream::readAhead): the values advance() would compute; and from the
    /// light pairs, the emitters' samples at those paths' points (WavefrontBatch::emitterSamples), and from the
    /// estimator's pairs its directions where it draws ahead (WavefrontBatch::draws).
    void fillAhead(WavefrontBatch& batch, std::size_t count, std::uint32_t spp, int depth) const;
    /// The vertex that w's ray reached: its terms in `terms`; Continues with w set to the continuing ray (depth + 1),
    /// Ends where the path ends (terms.own then the path's last value: the vertex's own terms, or what the ray
    /// met leaving the scene). `lit`: its light sample waits for its shadow ray (`shadow`, `light`), which the
    /// caller traces with the depth's others and whose term it adds to terms.own where the ray is clear.
    /// `ahead`: what fillAhead drew for the vertex (its emitter sample, its estimator's direction).
    /// A first hit whose directions branch (a set, or --split k): Branches, w left at its first hit, its own terms
    /// in terms.own and its continuations in `spawned`, `branches` of them (spawnBranches).
    VertexStep advance(WavePath& w, VertexTerms& terms, PathContext& pc, const VertexAhead& ahead, ShadowRay& shadow, LightSample& light,
                       bool& lit, std::size_t& branches, FirstHitBranch* spawned) const;
    /// continuePath's continuations of a branching first hit (dirs.size() > 1), each past its roulette, in `out`
    /// (their number returned) instead of traced.
    std::size_t spawnBranches(const DirectionList& dirs, const Frame& frame, const Vec3& ng, const Vec3& p, bool shadowed,
                              const Color& throughput, SampleStream& samples, TraceStats& stats, FirstHitBranch* out) const;
    /// advance()'s light sample (directLight up to its shadow ray): from its emitter sample drawn ahead, or its
    /// stream at its path's dimensions; true where its shadow ray is to be traced.
    bool vertexLightSample(std::uint64_t path, const VertexAhead& ahead, const Vec3& p, const Vec3& ng, const Frame& frame,
                           const ShadingContext& sc, bool shadowed, SampleStream& samples, ShadowRay& shadow, LightSample& light) const;
    /// advance()'s directions: the first hit's (firstHitDirections), or drawn ahead, or from its stream at its
    /// path's dimensions.
    void vertexDirections(const ShadingContext& sc, std::uint64_t path, const DirectionDraw* drawn, SampleStream& samples,
                          DirectionList& dirs) const;
    /// A depth of the batch's first `count` live paths (`cameras`: its camera samples, streams[k] theirs): each
    /// one's vertex (advance), their shadow rays together, a branching first hit's continuations in their slots;
    /// the number of paths that go on, first in b.live.
    std::size_t takeVertices(WavefrontBatch& b, std::size_t count, std::size_t cameras, int depth, SampleStream* streams, bool ahead,
                             TraceStats& stats, PathScratch& scratch) const;
    /// cameraRadiances of the same camera rays with their paths taken depth by depth: every path's vertex at
    /// depth d before any path's at d + 1.
    void cameraRadiancesWavefront(const Vec3& o, const Vec3* dirs, std::size_t n, SampleStream* streams, Color* out, TraceStats& stats,
                                  PathScratch& scratch) const;
    /// The vertex that o + t d reached (hit, or nullptr when it left the scene): its emission, NEE and
    /// continuation.
    Color shade(const Vec3& o, const Vec3& d, const Hit* hit, int depth, std::uint64_t path, double prevMisPdf, const Color& throughput,
                PathContext& pc) const;
    /// A branching vertex's rays, traced together from `origin` and each continued as its own path.
    Color traceBundle(const Vec3& origin, RayBundle& bundle, int depth, PathContext& pc) const;
    /// The shading normal on ng's side (the vertex normals', bent by a normal or bump map where it can be:
    /// `bent`). Inline where it is the triangle's own normal (no vertex normals, no map): a call returning its
    /// Vec3 through memory cost the wavefront's vertex a wait on that memory (docs/performance.md).
    [[gnu::always_inline]] Vec3 shadingNormal(const Triangle& tri, const Hit& hit, const Vec3& ng, const MaterialTextures& textures,
                                              const TexCoord& uv, const Vec3& wo, bool& bent) const {
        if (tri.n[0] >= 0 || textures.perturbsNormal()) return smoothShadingNormal(tri, hit, ng, textures, uv, wo, bent);
        bent = false;
        const Vec3& ns = geometricNormals_[hit.prim];
        return ns * (dot(ns, ng) < 0 ? -1.0 : 1.0);
    }
    /// shadingNormal where the triangle has vertex normals or its material a normal or bump map.
    Vec3 smoothShadingNormal(const Triangle& tri, const Hit& hit, const Vec3& ng, const MaterialTextures& textures, const TexCoord& uv,
                             const Vec3& wo, bool& bent) const;
    double emissionWeight(const Hit& hit, const Vec3& d, int depth, double prevMisPdf) const;
    /// A sampled direction `s` at a vertex (shading frame `frame`, geometric normal `ng`) as it leaves the
    /// surface: its world direction `wi` and its weight (times bumpShadowing where `shadowed`); false, and
    /// nothing traced, where it points below the surface by either normal: no light comes through there.
    /// The test of every continuation (traceContinuation, traceDirection; continuePath writes it out).
    [[gnu::always_inline]] static bool leavesSurface(const DirectionSample& s, const Frame& frame, const Vec3& ng, bool shadowed, Vec3& wi,
                                                     Color& weight) {
        wi = frame.toWorld(s.wi);
        if (s.wi.z <= 0 || dot(wi, ng) <= 0) return false;
        weight = shadowed ? s.weight * bumpShadowing(ng, frame.n, wi) : s.weight;
        return true;
    }
    /// The continuations of a vertex without --splitting ears: the estimator's directions (k calls at the
    /// first hit with --split k), each past Russian roulette by throughput.
    Color continuePath(const ShadingContext& sc, const Frame& frame, const Vec3& ng, const Vec3& p, bool shadowed, int depth,
                       std::uint64_t path, const Color& throughput, PathContext& pc) const;
    /// --splitting ears: the factor q of a vertex in finest cell `finest` with this throughput (splitting/ears.h, at least 1
    /// before the roulette depth; where no cell has an estimate yet, 1 before the roulette depth and the
    /// throughput's largest component, at most 0.95, from it on).
    double continuationFactor(std::size_t finest, const Color& throughput, int depth) const;
    /// --splitting ears: fetches into the cache the entries of finest cell `finest` that continuationFactor
    /// and misScale will read at this depth (a hint: no effect on any value).
    void prefetchFactor(std::size_t finest, int depth) const;
    /// --splitting ears: the number of estimator calls that a vertex with factor q stands for in MIS: q, at
    /// the first hit 1 + (q - 1) t with its cell's learned MIS share t (splitting/ears.h misShare) where it
    /// has one.
    double misScale(std::size_t finest, double q, int depth) const;
    /// --splitting ears, resting (setResting): continuationFactor of a cell without estimates, 1 at the first hit.
    double restingFactor(const Color& throughput, int depth) const;
    /// --splitting ears: floor(q + u) = n continuations (at the first hit a power of two), averaged (weight 1/n; under roulette, q < 1,
    /// 1/q), their directions' MIS densities times `mis` (misScale); each is reported with its value and rays in
    /// scratch.splitRecords (in cell `cell`, the vertex's finest) unless this is the render's last epoch. Continuation j >= 1 starts a
    /// path of its own (SampleDimensions::splitPath), and at the first hit reads the estimator as block
    /// point j of its sample (SampleStream::blockContinuation): no two calls in a pixel share a number.
    /// --splitting ears-orbit: the orbit of n symmetric copies that a first hit's n continuations follow, copy
    /// j in copies[j] (in the scratch, not in splitContinuations' frame: a local orbit there, even unused,
    /// was zeroed on every call, 14% of that function's time).
    void firstHitOrbit(const ShadingContext& sc, SampleStream& samples, std::uint32_t n, std::array<Vec3, 8>& copies) const;
    Color splitContinuations(const ShadingContext& sc, const Frame& frame, const Vec3& ng, const Vec3& p, std::size_t cell, bool shadowed,
                             double q, double mis, int depth, std::uint64_t path, const Color& throughput, PathContext& pc) const;
    /// --splitting ears: a vertex after the first hit with q <= 1: splitContinuations for n <= 1, without its loop.
    Color rouletteContinuation(const ShadingContext& sc, const Frame& frame, const Vec3& ng, const Vec3& p, std::size_t cell, bool shadowed,
                               double q, int depth, std::uint64_t path, const Color& throughput, PathContext& pc) const;
    /// --splitting ears: a first hit whose factor is 1: splitContinuations for n = 1, without its loop.
    Color singleFirstHit(const ShadingContext& sc, const Frame& frame, const Vec3& ng, const Vec3& p, std::size_t cell, bool shadowed,
                         std::uint64_t path, const Color& throughput, PathContext& pc) const;
    /// --splitting ears: one continuation's directions traced from `origin` (weights 1/divisor, MIS densities
    /// times `mis`) and, with `record`, reported in scratch.splitRecords (a first hit's also as a BrdfHit
    /// record); `traced` counts the rays it started.
    Color traceContinuation(const DirectionList& dirs, const Frame& frame, const Vec3& ng, const Vec3& origin, bool shadowed, double mis,
                            double divisor, int depth, std::uint64_t own, const Color& throughput, bool record, std::size_t cell,
                            ears::Section section, std::uint64_t& traced, PathContext& pc) const;
    /// --splitting ears: traceContinuation of one direction, without its records: its radiance times its
    /// weight (0 below the surface), MIS density times `mis`, throughput divided by `divisor`.
    Color traceDirection(const DirectionSample& s, const Frame& frame, const Vec3& ng, const Vec3& origin, bool shadowed, double mis,
                         double divisor, int depth, std::uint64_t path, const Color& throughput, PathContext& pc) const;
    /// The estimator's directions at the first hit (first-bounce stream, joint pattern, splitting). `drawn`: where
    /// the wavefront drew them ahead (Estimator::drawAhead; no joint pattern), one draw, or --split k's k.
    void firstHitDirections(const ShadingContext& sc, SampleStream& samples, DirectionList& dirs,
                            const DirectionDraw* drawn = nullptr) const;
    /// Next-event estimation: one emitter chosen in proportion to its power, one direction towards it
    /// (the same for every kind of emitter), its shadow ray, and the power heuristic against the
    /// estimator's density (none for a delta emitter, which no path can hit).
    /// `shadowed`: the BRDF times bumpShadowing (--bump-shadowing at a bent normal).
    /// Traced before the vertex's continuations are decided: its MIS weight waits for their number
    /// (DirectLight::value), so that --splitting ears looks its factor up after the shadow ray, whose
    /// traversal hides the wait for the factor's cache line.
    DirectLight directLight(const Vec3& p, const Vec3& ng, const Frame& frame, const ShadingContext& sc, Point2 u, TraceStats& stats,
                            bool shadowed) const;
    /// directLight's steps before and after its shadow ray, for the wavefront, which traces a depth's shadow
    /// rays together: false where the sample contributes nothing (no shadow ray); else its shadow ray and what
    /// it contributes once the ray is clear (litBy).
    bool lightSample(const Vec3& p, const Vec3& ng, const Frame& frame, const ShadingContext& sc, Point2 u, bool shadowed, ShadowRay& ray,
                     LightSample& ls) const;
    DirectLight litBy(const LightSample& ls) const;
    /// lightSample after its emitter's sample `s` (`sampled`: what SceneEmitters::sample returned).
    bool lightSampleOf(bool sampled, const EmitterSample& s, const Vec3& p, const Vec3& ng, const Frame& frame, const ShadingContext& sc,
                       bool shadowed, ShadowRay& ray, LightSample& ls) const;
    /// Radiance of a ray that left the scene along d: the background (MIS-weighted against its light
    /// sampling from the previous vertex when it is light-sampled); `emitted`: the background unweighted.
    Color escaped(const Vec3& d, int depth, double prevMisPdf, Color& emitted) const;

    const Scene& scene_;
    const Accel& accel_;
    const Estimator& estimator_;
    TraceSettings settings_;
    const ears::Learning* learning_;
    bool records_;                        ///< --splitting ears: whether deeper vertices' continuations are reported
    bool resting_ = false;                ///< --splitting ears: EARS rests (setResting)
    bool firstHitRecords_;                ///< and the first hit's (FirstHit, FirstHitVertex) among them
    std::vector<Vec3> geometricNormals_;  ///< unit, counter-clockwise winding
    std::vector<std::uint8_t> textured_;  ///< per material: whether it has any texture (one byte to test on the hot path)
    std::vector<double> areas_;
    SceneEmitters emitters_;
    bool triangleSampling_;     ///< NEE + MIS of emissive triangles: asked for, possible with this estimator, and some emit
    bool environmentSampling_;  ///< NEE + MIS of the environment map, on the same terms as the triangles
    bool lightSampling_;        ///< NEE at all: triangles or environment as above, or delta lights (always sampled)
    std::size_t firstHitBranches_;  ///< firstHitBranches()
    bool wavefront_;                ///< tracesAsWavefront()
    double epsilon_ = 1e-4;     ///< ray offset, relative to the scene's size
};

}  // namespace symphong
