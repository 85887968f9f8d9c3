#include "render/path_tracer.h"
#include "render/next_event.h"
#include "sampling/sobol_lanes.h"

#include "math/frame.h"
#include "scene/shading_normal.h"
#include "scene/surface.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace symphong {

// A first-hit vertex's continuations are a block of its sample's block points (SampleStream::blockContinuation).
static_assert(ears::kMaxFactor <= kBlockSize, "a vertex's continuations must fit one block");

namespace {

std::vector<double> triangleAreas(const Scene& s, std::vector<Vec3>& normals) {
    std::vector<double> areas(s.triangles.size());
    normals.resize(s.triangles.size());
    for (std::size_t i = 0; i < s.triangles.size(); ++i) {
        const auto& t = s.triangles[i];
        const Vec3 c = cross(s.positions[t.v[1]] - s.positions[t.v[0]], s.positions[t.v[2]] - s.positions[t.v[0]]);
        const double len = length(c);
        areas[i] = 0.5 * len;
        normals[i] = len > 0 ? c / len : Vec3(0, 0, 1);
    }
    return areas;
}

/// Power heuristic (beta = 2) weight of a strategy with density a against one with density b.
double powerHeuristic(double a, double b) {
    if (a <= 0) return 0.0;
    if (b <= 0) return 1.0;
    const double a2 = a * a, b2 = b * b;
    return a2 / (a2 + b2);
}

}  // namespace

Color DirectLight::value(double misScale) const {
    if (delta) return unweighted;  // the same for every vertex of a scene's delta emitter: predicted
    // powerHeuristic(lightPdf, b) without its tests, which lightPdf > 0 and b >= 0 make moot (1 exactly at b = 0).
    const double a2 = lightPdf * lightPdf, b = estimatorPdf * misScale;
    return unweighted * (cosine * (a2 / (a2 + b * b)) / lightPdf);
}

PathTracer::PathTracer(const Scene& scene, const Accel& accel, const Estimator& estimator, TraceSettings settings,
                       const ears::Learning* learning, bool records)
    : scene_(scene),
      accel_(accel),
      estimator_(estimator),
      settings_(settings),
      learning_(learnsFactors(settings.splitting) ? learning : nullptr),
      records_(records),
      firstHitRecords_(records),
      areas_(triangleAreas(scene, geometricNormals_)),
      emitters_(scene, areas_, geometricNormals_, settings.nextEvent && estimator.combinesWithLightSampling()),
      triangleSampling_(emitters_.samplesTriangles()),
      environmentSampling_(emitters_.samplesBackground()),
      lightSampling_(!emitters_.empty()),
      firstHitBranches_(static_cast<std::size_t>(std::max(1, settings.firstHitSplit)) * std::max<std::size_t>(1, estimator.largestSet())),
      wavefront_((settings.tracer == TracerChoice::Wavefront || (settings.tracer == TracerChoice::Automatic && sobolLanesAvailable() &&
                                                                 firstHitBranches_ <= kAutomaticWavefrontBranches)) &&
                 !learning_ && !settings.jointFirstBounce && firstHitBranches_ <= WavefrontBatch::kSize) {
    Vec3 lo, hi;
    scene.bounds(lo, hi);
    const double extent = std::max({length(hi - lo), maxComponent(vmax(vmax(hi, -hi), vmax(lo, -lo))), 1e-3});
    epsilon_ = 1e-5 * extent;
    // A library caller's k below 1 is one call (the command line refuses it): weighed as one everywhere.
    settings_.firstHitSplit = std::max(1, settings_.firstHitSplit);
    textured_.reserve(scene.materials.size());
    for (const PhongMaterial& m : scene.materials) textured_.push_back(m.textures.any() ? 1 : 0);
}

void PathTracer::prepare(PathScratch& scratch) const {
    const std::size_t depths = static_cast<std::size_t>(settings_.maxDepth) + 1;
    if (scratch.directions.size() >= depths) return;
    scratch.directions.resize(depths);
    scratch.bundles.resize(depths);
    scratch.materials.resize(depths);
}

Color PathTracer::cameraRadiance(const Vec3& o, const Vec3& d, SampleStream& samples, TraceStats& stats, PathScratch& scratch) const {
    prepare(scratch);
    PathContext pc{samples, stats, scratch};
    return radiance(o, d, 0, 0, 0.0, Color(1.0), pc);
}

// The camera rays as one packet: they share the eye and point into neighbouring pixels, so Embree's coherent packet
// traversal visits the BVH's nodes once for all of them (radiance() traces depth 0 with tnear 0, tfar inf:
// the same query).
void PathTracer::cameraRadiances(const Vec3& o, const Vec3* dirs, std::size_t n, SampleStream* streams, Color* out, TraceStats& stats,
                                 PathScratch& scratch) const {
    if (tracesAsWavefront()) return cameraRadiancesWavefront(o, dirs, n, streams, out, stats, scratch);
    prepare(scratch);
    std::array<Hit, kCameraPacket> hits;
    std::array<bool, kCameraPacket> found;
    n = std::min(n, kCameraPacket);
    accel_.intersectBundle(o, dirs, n, 0.0, hits.data(), found.data(), true);
    stats.rays += n;
    for (std::size_t k = 0; k < n; ++k) {
        PathContext pc{streams[k], stats, scratch};
        out[k] = shade(o, dirs[k], found[k] ? &hits[k] : nullptr, 0, 0, 0.0, Color(1.0), pc);
    }
}

// One path vertex: emission (MIS-weighted against light sampling when the previous vertex could also
// have reached it by NEE), then NEE, then the estimator's directions, each continued recursively.
Color PathTracer::radiance(const Vec3& o, const Vec3& d, int depth, std::uint64_t path, double prevMisPdf, const Color& throughput,
                           PathContext& pc) const {
    Hit hit;
    ++pc.stats.rays;
    const bool found = accel_.intersect(o, d, depth == 0 ? 0.0 : epsilon_, std::numeric_limits<double>::infinity(), hit);
    return shade(o, d, found ? &hit : nullptr, depth, path, prevMisPdf, throughput, pc);
}

// The MIS weight of emission that a path found after a vertex with density prevMisPdf: against light
// sampling's density of the same direction (0 for a triangle it does not sample); 1 from the camera.
double PathTracer::emissionWeight(const Hit& hit, const Vec3& d, int depth, double prevMisPdf) const {
    if (depth == 0 || !triangleSampling_) return 1.0;
    return powerHeuristic(prevMisPdf, emitters_.trianglePdfOfHit(hit.prim, d, hit.t));
}

// The interpolated vertex normal (or the geometric one) bent by the material's normal or bump map, on
// the side of ng (the geometric normal facing the ray). Where the map bends it so far that the viewer
// (wo, towards the eye) or ng falls behind it, the unbent normal: the map cannot be honoured there, and
// a black spot would be worse.
Vec3 PathTracer::smoothShadingNormal(const Triangle& tri, const Hit& hit, const Vec3& ng, const MaterialTextures& textures,
                                     const TexCoord& uv, const Vec3& wo, bool& bent) const {
    bent = false;
    Vec3 ns = geometricNormals_[hit.prim];
    if (tri.n[0] >= 0) {
        const double b0 = 1.0 - hit.u - hit.v;
        ns = normalize(scene_.normals[tri.n[0]] * b0 + scene_.normals[tri.n[1]] * hit.u + scene_.normals[tri.n[2]] * hit.v);
    }
    const double side = dot(ns, ng) < 0 ? -1.0 : 1.0;
    if (textures.perturbsNormal()) {
        const Vec3 mapped = perturbedNormal(scene_, tri, textures, hit.u, hit.v, uv, ns) * side;
        if (dot(mapped, wo) > 0 && dot(mapped, ng) > 0) {
            bent = true;
            return mapped;
        }
    }
    return ns * side;
}

// --splitting ears (both inline: once per path vertex, from shade).
inline void PathTracer::prefetchFactor(std::size_t finest, int depth) const {
    const ears::Factors& f = learning_->factors;
    if (f.empty()) return;
    if (depth == 0) {
        __builtin_prefetch(&f.firstHit[finest]);
        __builtin_prefetch(&f.misShare[finest]);
    } else {
        __builtin_prefetch(&f.momentRatio[finest]);
        __builtin_prefetch(&f.varianceRatio[finest]);
    }
}

inline double PathTracer::continuationFactor(std::size_t finest, const Color& throughput, int depth) const {
    const ears::Factors& f = learning_->factors;
    if (depth == 0) {
        // The first hit's factor is solved for its cell (splitting/ears.h learnFactors) and rounded to a
        // power of two (firstHitBlock); where no cell has one yet, two continuations, so that the next
        // epoch learns the within-vertex variance there.
        // learnFactors gave every finest cell its nearest estimate (Factors): one lookup, no walk up the levels.
        return !f.empty() && f.firstHit[finest] >= 0 ? ears::firstHitBlock(f.firstHit[finest]) : ears::kUnknownFirstHitFactor;
    }
    double q = 1;
    if (!f.empty() && f.momentRatio[finest] >= 0) {
        q = ears::splittingFactor(luminance(throughput), f.varianceRatio[finest], f.momentRatio[finest], f.scale);
        if (depth + 1 < settings_.rrDepth)
            q = std::max(q, 1.0);  // no roulette before the roulette depth (EARS's rrDepth)
        else if (settings_.earsRouletteFloor)
            q = ears::flooredRoulette(q, ears::throughputSurvival(maxComponent(throughput)));
    } else if (depth + 1 >= settings_.rrDepth) {
        q = ears::throughputSurvival(maxComponent(throughput));
    }
    return q;
}

// A resting EARS's factor: continuationFactor's where no cell has an estimate, but 1 at the first hit (its
// learned factors split nothing there): plain roulette by the vertex's throughput from the roulette depth on.
inline double PathTracer::restingFactor(const Color& throughput, int depth) const {
    return depth == 0 || depth + 1 < settings_.rrDepth ? 1.0 : ears::throughputSurvival(maxComponent(throughput));
}

inline double PathTracer::misScale(std::size_t finest, double q, int depth) const {
    const ears::Factors& f = learning_->factors;
    return depth == 0 && !f.empty() && f.misShare[finest] >= 0 ? 1 + (q - 1) * f.misShare[finest] : q;
}

Color PathTracer::shade(const Vec3& o, const Vec3& d, const Hit* found, int depth, std::uint64_t path, double prevMisPdf,
                        const Color& throughput, PathContext& pc) const {
    if (!found) {
        Color emitted;
        const Color L = escaped(d, depth, prevMisPdf, emitted);
        if (depth == 1 && environmentSampling_) pc.scratch.bounceEmission = emitted;  // for a first hit's BrdfHit record
        return L;
    }
    const Hit& hit = *found;
    const Triangle& tri = scene_.triangles[hit.prim];
    const PhongMaterial& baseMaterial = scene_.materials[tri.material];
    // A textured material's parameters at this point, in this depth's scratch material. (render/wavefront.cpp's
    // advance() reads the hit the same way: through one helper returning the five, this function took 0.3% more
    // instructions of the default render, callgrind at 64x64, 16 spp, one thread: 478.9 M against 477.4 M.)
    const bool textured = textured_[tri.material] != 0;
    const TexCoord uv = textured ? texcoordAt(scene_, tri, hit.u, hit.v) : TexCoord{};
    const PhongMaterial& mat =
        textured ? materialAt(scene_, baseMaterial, uv, pc.scratch.materials[static_cast<std::size_t>(depth)]) : baseMaterial;
    const Vec3 p = o + d * hit.t;
    // --splitting ears: the vertex's finest cell of the learned grid, found once for its factor and its
    // continuations' records; the factor's entries are fetched into the cache now, while the shading
    // below hides the wait (the tables are scattered over hundreds of kilobytes: a miss each vertex).
    // A resting EARS (setResting) looks nothing up: its vertices take the factors of cells without estimates.
    const bool learned = learning_ && !resting_;
    const std::size_t cell = learned ? learning_->grid.cell(p, ears::Grid::kLevels - 1) : 0;
    if (learned) prefetchFactor(cell, depth);
    Vec3 ng = geometricNormals_[hit.prim];
    const bool frontFace = dot(ng, d) < 0;

    Color L(0.0);
    if (mat.isEmissive() && frontFace) {
        const Color emitted = textured ? emissionAt(scene_, baseMaterial, uv) : mat.emission;
        if (depth == 1 && triangleSampling_) pc.scratch.bounceEmission = emitted;  // for a first hit's BrdfHit record
        L += emitted * emissionWeight(hit, d, depth, prevMisPdf);
    }
    if (depth >= settings_.maxDepth) return L;

    if (!frontFace) ng = -ng;
    const Vec3 toEye = normalize(-d);
    bool bent = false;
    const Frame frame = Frame::fromNormal(shadingNormal(tri, hit, ng, baseMaterial.textures, uv, toEye, bent));
    // --bump-shadowing: a bent normal's shading times Chiang et al.'s shadowing term (scene/shading_normal.h).
    const bool shadowed = bent && settings_.bumpShadowing;
    const Vec3 wo = frame.toLocal(toEye);
    if (wo.z <= 0) return L;  // seen from behind its shading normal: reflects nothing

    const ShadingContext sc{wo, &mat, depth, depth == 0};
    SampleStream& samples = pc.samples;
    const std::uint64_t vertexDim = SampleDimensions::vertex(depth, path);
    DirectLight direct;
    if (lightSampling_) {
        samples.setDimension(vertexDim + SampleDimensions::kLight);
        direct = directLight(p, ng, frame, sc, samples.get2D(), pc.stats, shadowed);
    }
    // --splitting ears decides the vertex's continuations after the shadow ray (its factor's cache line has
    // arrived by then) and before light sampling's MIS weight, which needs q.
    const double q = learned ? continuationFactor(cell, throughput, depth) : learning_ ? restingFactor(throughput, depth) : 0.0;
    if (q > 0) {
        const double mis = learned ? misScale(cell, q, depth) : q;
        if (lightSampling_) L += direct.value(mis);
        if (depth > 0 && q <= 1) return L + rouletteContinuation(sc, frame, ng, p, cell, shadowed, q, depth, path, throughput, pc);
        if (depth == 0 && q == 1) return L + singleFirstHit(sc, frame, ng, p, cell, shadowed, path, throughput, pc);
        return L + splitContinuations(sc, frame, ng, p, cell, shadowed, q, mis, depth, path, throughput, pc);
    }
    if (lightSampling_) L += direct.value(depth == 0 ? settings_.firstHitSplit : 1);
    return L + continuePath(sc, frame, ng, p, shadowed, depth, path, throughput, pc);
}

// The estimator's directions at a vertex (one call; k at the first hit with --split), each continued
// past Russian roulette: one direction continues this path, a set's directions are traced as a bundle.
Color PathTracer::continuePath(const ShadingContext& sc, const Frame& frame, const Vec3& ng, const Vec3& p, bool shadowed, int depth,
                               std::uint64_t path, const Color& throughput, PathContext& pc) const {
    SampleStream& samples = pc.samples;
    DirectionList& dirs = pc.scratch.directions[static_cast<std::size_t>(depth)];
    dirs.clear();
    if (depth == 0) {
        firstHitDirections(sc, samples, dirs);
    } else {
        samples.setDimension(SampleDimensions::vertex(depth, path) + SampleDimensions::kEstimator);
        estimator_.sample(sc, samples, dirs);
    }
    const Vec3 origin = p + ng * epsilon_;
    // `throughput` only steers Russian roulette. A branch of a K-direction set carries about 1/K of the
    // set's light; judging it by K times its weight keeps roulette from killing the branches of a set.
    // A set's directions continue as paths 1..K of their own (their own dimensions); one direction
    // continues this path.
    const double branches = static_cast<double>(std::max<std::size_t>(1, dirs.size()));
    const bool branching = dirs.size() > 1;
    // Only a set too large to go ray by ray anyway (Accel::kSingleRaysUpTo: --split 2's pair, a small set)
    // gathers its rays into a bundle for packets; a single direction, or each of a small set's, continues
    // at once: the same queries, paths and sums in the same order, without the bundle's bookkeeping.
    const bool bundled = dirs.size() > Accel::kSingleRaysUpTo;
    RayBundle* bundle = nullptr;
    Color L(0.0);
    std::uint64_t traced = 0;
    if (bundled) {
        bundle = &pc.scratch.bundles[static_cast<std::size_t>(depth)];
        bundle->rays.clear();
        bundle->dirs.clear();
    }
    for (std::size_t k = 0; k < dirs.size(); ++k) {
        const DirectionSample& s = dirs[k];
        // leavesSurface's test, written out: through the helper (always inline) this loop cost 0.3% more
        // instructions of the default render (callgrind, cornell 128x128, 16 spp: 1,849.2 M against 1,843.6 M).
        const Vec3 wi = frame.toWorld(s.wi);
        if (s.wi.z <= 0 || dot(wi, ng) <= 0) continue;  // below the surface: no light comes through it
        const std::uint64_t nextPath = branching ? k + 1 : path;
        const Color weight = shadowed ? s.weight * bumpShadowing(ng, frame.n, wi) : s.weight;
        Color next = throughput * weight * branches;
        double survive = 1.0;
        if (depth + 1 >= settings_.rrDepth) {
            survive = std::min(0.95, maxComponent(next));
            samples.setDimension(SampleDimensions::vertex(depth + 1, nextPath) + SampleDimensions::kRoulette);
            if (!(survive > 0) || samples.get1D() >= survive) continue;
            next /= survive;
        }
        if (!branching) return weight * radiance(origin, wi, depth + 1, nextPath, s.misPdf, next, pc) / survive;
        if (!bundled) {
            L += weight * radiance(origin, wi, depth + 1, nextPath, s.misPdf, next, pc) / survive;
            ++traced;
            continue;
        }
        bundle->dirs.push_back(wi);
        bundle->rays.push_back({weight, next, s.misPdf, survive, nextPath});
    }
    if (!bundled) {
        if (traced > 1) pc.stats.extraPaths += traced - 1;  // as traceBundle counts a bundle's rays beyond the first
        return L;
    }
    if (bundle->rays.empty()) return Color(0.0);
    return traceBundle(origin, *bundle, depth, pc);
}

// A set's surviving rays share their origin: one closest-hit query for all of them (16-wide packets),
// then each continues as its own path.
Color PathTracer::traceBundle(const Vec3& origin, RayBundle& bundle, int depth, PathContext& pc) const {
    const std::size_t n = bundle.rays.size();
    if (bundle.capacity < n) {
        bundle.found = makeCacheLineArray<bool>(n);
        bundle.capacity = n;
    }
    bundle.hits.resize(n);
    accel_.intersectBundle(origin, bundle.dirs.data(), n, epsilon_, bundle.hits.data(), bundle.found.get());
    pc.stats.rays += n;
    pc.stats.extraPaths += n - 1;  // n >= 1: each ray of the bundle starts a path, the first continues the camera's
    Color L(0.0);
    for (std::size_t i = 0; i < n; ++i) {
        const RayBundle::Ray& r = bundle.rays[i];
        const Hit* hit = bundle.found[i] ? &bundle.hits[i] : nullptr;
        L += r.weight * shade(origin, bundle.dirs[i], hit, depth + 1, r.path, r.misPdf, r.next, pc) / r.survive;
    }
    return L;
}

// The first hit's directions: from the first-hit block of the sampler (another block for another
// --first-bounce-stream), through a JointPairView for --joint-first-bounce, and k calls on the camera
// sample's k sub-samples for --split k (each direction's weight / k, its set density x k).
void PathTracer::firstHitDirections(const ShadingContext& sc, SampleStream& samples, DirectionList& dirs,
                                    const DirectionDraw* drawn) const {
    const std::uint64_t dim = SampleDimensions::firstHitEstimator(settings_.firstBounceStream);
    samples.setDimension(dim);
    if (settings_.jointFirstBounce && settings_.firstHitSplit <= 1) {
        const JointPairView joint(samples.sampler(), dim, SampleDimensions::kPixel);
        SampleStream stream = samples.through(joint);
        estimator_.sample(sc, stream, dirs);
        return;
    }
    if (settings_.firstHitSplit <= 1) {
        if (drawn)
            estimator_.sampleDrawn(sc, *drawn, dirs);
        else
            estimator_.sample(sc, samples, dirs);
        return;
    }
    // The partner pair is matched to the camera samples, not to their sub-samples: no joint pair when split.
    const std::uint32_t k = static_cast<std::uint32_t>(settings_.firstHitSplit);
    for (std::uint32_t j = 0; j < k; ++j) {
        const std::size_t first = dirs.size();
        if (drawn) {
            estimator_.sampleDrawn(sc, drawn[j], dirs);
        } else {
            SampleStream sub = samples.split(j, k);
            estimator_.sample(sc, sub, dirs);
        }
        for (std::size_t i = first; i < dirs.size(); ++i) {
            dirs[i].weight /= static_cast<double>(k);
            dirs[i].misPdf *= static_cast<double>(k);
        }
    }
}

// Next-event estimation, the same for every emitter: one chosen in proportion to its power, a direction
// towards it, the shadow ray, and f cos / p weighted against the estimator by the power heuristic (a
// delta emitter: f E cos / pick, no MIS, since no path can hit it).
DirectLight PathTracer::directLight(const Vec3& p, const Vec3& ng, const Frame& frame, const ShadingContext& sc, Point2 u,
                                    TraceStats& stats, bool shadowed) const {
    ShadowRay ray;
    LightSample ls;
    if (!lightSample(p, ng, frame, sc, u, shadowed, ray, ls)) return DirectLight{};
    ++stats.rays;
    if (accel_.occluded(ray.o, ray.d, 0.0, ray.tfar)) return DirectLight{};
    DirectLight out = litBy(ls);
    if (!out.delta) out.estimatorPdf = estimator_.misPdf(sc, ls.wiLocal);  // only for a clear ray
    return out;
}

Color PathTracer::escaped(const Vec3& d, int depth, double prevMisPdf, Color& emitted) const {
    const Vec3 dir = normalize(d);
    const Emitter& background = emitters_.background();
    if (!(depth > 0 && environmentSampling_)) {
        emitted = background.backgroundRadiance(dir);
        return emitted;
    }
    double pdf = 0;
    emitted = background.backgroundRadianceAndPdf(dir, emitters_.backgroundProbability(), pdf);
    return emitted * powerHeuristic(prevMisPdf, pdf);
}

}  // namespace symphong
