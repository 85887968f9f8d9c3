// A batch of camera samples' paths depth by depth (PathTracer's members for it; the recursive tracer is in
// path_tracer.cpp; the batch's state in wavefront.h): every path of the batch takes its vertex at depth d before any
// takes its vertex at d + 1, each vertex keeping its terms (VertexTerms) and handing on the next ray, instead of
// shade() calling itself for the next vertex and adding on the way back; a depth's shadow rays, then its
// continuing rays, go to Embree together (Accel::occludedEach, intersectEach: 16-wide packets), and the sampler's
// values of a depth's vertices are computed together in vector lanes (sobol_lanes.h), and from them the vertices'
// light samples and estimator directions (fillAhead: lanes too, where they run). The same decisions at the
// same sample dimensions as the recursive tracer, so the same paths, and each path's terms summed at its end from
// the last vertex back, in shade()'s order: the same radiance bit for bit where Embree answers each query as the
// single-ray one does (an Accel without packets); with packets, the same but for the rare grazing ray that a
// packet's kernels round otherwise (docs/performance.md "The second tracer", "Shadow and bounce rays in packets").
// A first hit that branches (a set estimator's directions, --split k) hands each further continuation a slot of
// its own, with its own path's dimensions (SampleDimensions::vertex(depth, j + 1)), and its value joins the first
// hit's as continuePath adds its branches up.
#include "math/frame.h"
#include "render/next_event.h"
#include "render/path_tracer.h"
#include "sampling/sobol_lanes.h"
#include "scene/shading_normal.h"
#include "scene/surface.h"

#include <algorithm>
#include <stdexcept>

namespace symphong {

namespace {

/// The estimator's calls at a vertex of this depth: --split k's k at the first hit (one for k <= 1, as
/// firstHitDirections takes it), else one; fillAhead draws that many directions a path, from slot x calls on.
std::size_t estimatorCalls(const TraceSettings& settings, int depth) {
    return depth == 0 ? static_cast<std::size_t>(std::max(1, settings.firstHitSplit)) : 1;
}

/// Whether path w's vertex at this depth reads the sampler's values (fillAhead gives it a slot): at a surface,
/// below the depth limit.
bool readsAhead(const WavePath& w, int depth, const TraceSettings& settings) { return w.found && depth < settings.maxDepth; }

/// Path k's radiance from its last vertex back to its vertex at depth `down`, as shade()'s returns add it up.
Color radianceDownTo(const WavefrontBatch& b, std::size_t k, std::size_t down) {
    std::size_t d = static_cast<std::size_t>(b.paths[k].depth);
    Color L = b.terms[d][k].own;
    while (d-- > down) {
        const VertexTerms& t = b.terms[d][k];
        L = t.own + t.weight * L / t.survive;
    }
    return L;
}

/// Camera sample k's radiance: its path's, or a branching first hit's own terms plus its continuations' values
/// in their order (continuePath's sum: weight x radiance / survive each, added to zero).
Color cameraSampleRadiance(const WavefrontBatch& b, std::size_t k) {
    if (!b.branched[k]) return radianceDownTo(b, k, 0);
    const auto branch = [&](std::size_t s) { return b.terms[0][s].weight * radianceDownTo(b, s, 1) / b.terms[0][s].survive; };
    Color sum(0.0);
    if (b.paths[k].depth > 0) sum += branch(k);  // its first continuation, in its own slot
    for (std::size_t s = b.extraBegin[k]; s < b.extraEnd[k]; ++s) sum += branch(s);
    return b.terms[0][k].own + sum;
}

/// in's first `count` paths into `out` ordered by their path, in their order within each (a counting sort).
void groupByPath(const WavefrontBatch& b, const std::uint16_t* in, std::size_t count, std::uint16_t* out) {
    std::array<std::uint16_t, WavefrontBatch::kSize + 2> start{};  // paths 0..kSize
    for (std::size_t i = 0; i < count; ++i) ++start[b.paths[in[i]].path + 1];
    for (std::size_t p = 1; p < start.size(); ++p) start[p] = static_cast<std::uint16_t>(start[p] + start[p - 1]);
    for (std::size_t i = 0; i < count; ++i) out[start[b.paths[in[i]].path]++] = in[i];
}

/// Where valuesAhead puts a vertex's values: one of AheadValues' two pairs (the light sample's, the
/// estimator's), or its single value (the roulette's).
enum class AheadSlot { LightPair = 0, EstimatorPair = 1, Single };

/// The sampler's values for the paths at a surface (b.at's first b.runs[runCount]) at dimOf(their path), run by
/// run (b.runs): into their ahead values' `slot`.
template <class DimOf>
void valuesAhead(WavefrontBatch& b, std::size_t runCount, std::uint32_t spp, AheadSlot slot, DimOf dimOf) {
    for (std::size_t r = 0; r < runCount; ++r) {
        const std::size_t first = b.runs[r], size = b.runs[r + 1] - first;
        const std::uint64_t dim = dimOf(b.paths[b.at[first]].path);
        if (slot == AheadSlot::Single)
            sobolSingleValues(b.atKeys.data() + first, b.atIndices.data() + first, spp, dim, size, b.us.data() + first);
        else
            sobolPairValues(b.atKeys.data() + first, b.atIndices.data() + first, spp, dim, size, b.us.data() + first, b.vs.data() + first);
        for (std::size_t i = first; i < first + size; ++i) {
            AheadValues& a = b.ahead[b.at[i]];
            if (slot == AheadSlot::Single) {
                a.singleDim = dim;
                a.single = b.us[i];
            } else {
                a.pairDims[static_cast<int>(slot)] = dim;
                a.pairs[static_cast<int>(slot)] = {b.us[i], b.vs[i]};
            }
        }
    }
}

}  // namespace

std::uint64_t PathTracer::estimatorDimension(int depth, std::uint64_t path) const {
    return depth == 0 ? SampleDimensions::firstHitEstimator(settings_.firstBounceStream)
                      : SampleDimensions::vertex(depth, path) + SampleDimensions::kEstimator;
}

// shade() and continuePath() for a vertex (tracesAsWavefront): their code in their order, with the continuation
// handed back in `w` instead of traced (a branching first hit's continuations in `spawned`).
VertexStep PathTracer::advance(WavePath& w, VertexTerms& terms, PathContext& pc, const VertexAhead& ahead, ShadowRay& shadow,
                               LightSample& light, bool& lit, std::size_t& branches, FirstHitBranch* spawned) const {
    const int depth = w.depth;
    if (!w.found) {
        Color emitted;
        terms.own = escaped(w.d, depth, w.prevMisPdf, emitted);
        return VertexStep::Ends;
    }
    const Hit& hit = w.hit;
    // shade()'s lines, not a helper both call: path_tracer.cpp says what sharing them cost shade().
    const Triangle& tri = scene_.triangles[hit.prim];
    const PhongMaterial& baseMaterial = scene_.materials[tri.material];
    const bool textured = textured_[tri.material] != 0;
    const TexCoord uv = textured ? texcoordAt(scene_, tri, hit.u, hit.v) : TexCoord{};
    const PhongMaterial& mat =
        textured ? materialAt(scene_, baseMaterial, uv, pc.scratch.materials[static_cast<std::size_t>(depth)]) : baseMaterial;
    const Vec3 p = w.o + w.d * hit.t;
    Vec3 ng = geometricNormals_[hit.prim];
    const bool frontFace = dot(ng, w.d) < 0;
    Color L(0.0);
    if (mat.isEmissive() && frontFace) {
        const Color emitted = textured ? emissionAt(scene_, baseMaterial, uv) : mat.emission;
        L += emitted * emissionWeight(hit, w.d, depth, w.prevMisPdf);
    }
    // The vertex's own terms; the path ends here unless it continues below.
    const auto end = [&] {
        terms.own = L;
        return VertexStep::Ends;
    };
    if (depth >= settings_.maxDepth) return end();
    if (!frontFace) ng = -ng;
    const Vec3 toEye = normalize(-w.d);
    bool bent = false;
    const Frame frame = Frame::fromNormal(shadingNormal(tri, hit, ng, baseMaterial.textures, uv, toEye, bent));
    const bool shadowed = bent && settings_.bumpShadowing;
    const Vec3 wo = frame.toLocal(toEye);
    if (wo.z <= 0) return end();

    const ShadingContext sc{wo, &mat, depth, depth == 0};
    SampleStream& samples = pc.samples;
    // directLight up to its shadow ray, which the depth's loop traces with the others (its term is added to
    // `own` then: shadow's L += value(1), after the emission, in its order).
    if (lightSampling_) lit = vertexLightSample(w.path, ahead, p, ng, frame, sc, shadowed, samples, shadow, light);
    DirectionList& dirs = pc.scratch.directions[static_cast<std::size_t>(depth)];
    dirs.clear();
    vertexDirections(sc, w.path, ahead.direction, samples, dirs);
    if (dirs.size() > 1) {  // continuePath's branches
        terms.own = L;
        branches = spawnBranches(dirs, frame, ng, p, shadowed, w.throughput, samples, pc.stats, spawned);
        return VertexStep::Branches;
    }
    if (dirs.empty()) return end();
    const DirectionSample& s = dirs[0];
    const Vec3 wi = frame.toWorld(s.wi);
    if (s.wi.z <= 0 || dot(wi, ng) <= 0) return end();  // below the surface: no light comes through it
    const Color weight = shadowed ? s.weight * bumpShadowing(ng, frame.n, wi) : s.weight;
    Color next = w.throughput * weight;  // continuePath's throughput x weight x branches: one branch, x 1 exactly
    double survive = 1.0;
    if (depth + 1 >= settings_.rrDepth) {
        survive = std::min(0.95, maxComponent(next));
        samples.setDimension(SampleDimensions::vertex(depth + 1, w.path) + SampleDimensions::kRoulette);
        if (!(survive > 0) || samples.get1D() >= survive) return end();
        next /= survive;
    }
    terms.own = L;
    terms.weight = weight;
    terms.survive = survive;
    w.o = p + ng * epsilon_;
    w.d = wi;
    w.prevMisPdf = s.misPdf;
    w.throughput = next;
    ++w.depth;
    return VertexStep::Continues;
}

bool PathTracer::vertexLightSample(std::uint64_t path, const VertexAhead& ahead, const Vec3& p, const Vec3& ng, const Frame& frame,
                                   const ShadingContext& sc, bool shadowed, SampleStream& samples, ShadowRay& shadow,
                                   LightSample& light) const {
    bool lit;
    if (ahead.emitter) {
        lit = lightSampleOf(ahead.emitterSampled, *ahead.emitter, p, ng, frame, sc, shadowed, shadow, light);
    } else {
        samples.setDimension(SampleDimensions::vertex(sc.depth, path) + SampleDimensions::kLight);
        lit = lightSample(p, ng, frame, sc, samples.get2D(), shadowed, shadow, light);
    }
    if (lit && !light.light.delta) light.light.estimatorPdf = estimator_.misPdf(sc, light.wiLocal);  // sc's material: this vertex's
    return lit;
}

void PathTracer::vertexDirections(const ShadingContext& sc, std::uint64_t path, const DirectionDraw* drawn, SampleStream& samples,
                                  DirectionList& dirs) const {
    if (sc.depth == 0) {
        firstHitDirections(sc, samples, dirs, drawn);
    } else if (drawn) {
        estimator_.sampleDrawn(sc, *drawn, dirs);
    } else {
        samples.setDimension(estimatorDimension(sc.depth, path));
        estimator_.sample(sc, samples, dirs);
    }
}

std::size_t PathTracer::spawnBranches(const DirectionList& dirs, const Frame& frame, const Vec3& ng, const Vec3& p, bool shadowed,
                                      const Color& throughput, SampleStream& samples, TraceStats& stats, FirstHitBranch* out) const {
    if (dirs.size() > firstHitBranches_)
        throw std::logic_error("a first hit has more directions than its estimator's largestSet() x --split allow");
    const double branches = static_cast<double>(dirs.size());
    const Vec3 origin = p + ng * epsilon_;
    std::size_t count = 0;
    for (std::size_t k = 0; k < dirs.size(); ++k) {
        const DirectionSample& s = dirs[k];
        Vec3 wi;
        Color weight;
        if (!leavesSurface(s, frame, ng, shadowed, wi, weight)) continue;
        const std::uint64_t path = k + 1;
        Color next = throughput * weight * branches;
        double survive = 1.0;
        if (1 >= settings_.rrDepth) {
            survive = std::min(0.95, maxComponent(next));
            samples.setDimension(SampleDimensions::vertex(1, path) + SampleDimensions::kRoulette);
            if (!(survive > 0) || samples.get1D() >= survive) continue;
            next /= survive;
        }
        out[count++] = FirstHitBranch{origin, wi, s.misPdf, next, weight, survive, path};
    }
    if (count > 1) stats.extraPaths += count - 1;  // as continuePath counts them
    return count;
}

void PathTracer::cameraRadiancesWavefront(const Vec3& o, const Vec3* dirs, std::size_t n, SampleStream* streams, Color* out,
                                          TraceStats& stats, PathScratch& scratch) const {
    prepare(scratch);
    if (scratch.wavefront.empty()) scratch.wavefront.resize(1);
    WavefrontBatch& b = scratch.wavefront.front();
    n = std::min(n, cameraBatch());
    // The camera rays as Embree packets (cameraRadiances' coherent packets of kCameraPacket).
    for (std::size_t first = 0; first < n; first += kCameraPacket) {
        const std::size_t m = std::min(kCameraPacket, n - first);
        accel_.intersectBundle(o, dirs + first, m, 0.0, b.hits.data() + first, b.found.data() + first, true);
    }
    stats.rays += n;
    for (std::size_t k = 0; k < n; ++k) {
        // One initialisation, the other fields at their defaults: a zeroed WavePath{} with these assigned over
        // it stored each path twice (1.9% of a render).
        b.paths[k] = WavePath{o, dirs[k], b.hits[k], b.found[k]};
        b.live[k] = static_cast<std::uint16_t>(k);
        b.branched[k] = false;
    }
    // The sampler's values computed ahead: sobol streams of one pattern size (a render's camera samples), where
    // the lanes run; elsewhere computing them ahead would only move the same scalar work.
    const std::uint32_t spp = n > 0 ? streams[0].samplesPerPixel() : 0;
    bool ahead = n > 0 && sobolLanesAvailable();
    for (std::size_t k = 0; k < n && ahead; ++k) ahead = streams[k].sampler().isSobol() && streams[k].samplesPerPixel() == spp;
    if (ahead)
        for (std::size_t k = 0; k < n; ++k) {
            b.keys[k] = streams[k].pixelKey();
            b.indices[k] = streams[k].sampleIndex();
            streams[k].readAhead(&b.ahead[k]);
        }
    for (std::size_t count = n, depth = 0; count > 0; ++depth) {
        if (ahead) fillAhead(b, count, spp, static_cast<int>(depth));
        if (b.terms.size() <= depth) b.terms.resize(depth + 1);
        count = takeVertices(b, count, n, static_cast<int>(depth), streams, ahead, stats, scratch);
        for (std::size_t i = 0; i < count; ++i) {
            b.origins[i] = b.paths[b.live[i]].o;
            b.directions[i] = b.paths[b.live[i]].d;
        }
        accel_.intersectEach(b.origins.data(), b.directions.data(), count, epsilon_, b.hits.data(), b.found.data());
        stats.rays += count;
        for (std::size_t i = 0; i < count; ++i) {
            b.paths[b.live[i]].hit = b.hits[i];
            b.paths[b.live[i]].found = b.found[i];
        }
    }
    if (ahead)
        for (std::size_t k = 0; k < n; ++k) streams[k].readAhead(nullptr);
    for (std::size_t k = 0; k < n; ++k) out[k] = cameraSampleRadiance(b, k);
}

std::size_t PathTracer::takeVertices(WavefrontBatch& b, std::size_t count, std::size_t cameras, int depth, SampleStream* streams,
                                     bool ahead, TraceStats& stats, PathScratch& scratch) const {
    // Where the values are computed ahead, so are the emitter samples, for every path that reaches its light
    // sample, and the directions (a first hit under --split k: its k draws from slot x k on, fillAhead).
    const bool emittersAhead = ahead && lightSampling_;
    const bool directionsAhead = ahead && estimator_.drawsAhead(depth == 0);
    const std::size_t calls = estimatorCalls(settings_, depth);
    auto& terms = b.terms[static_cast<std::size_t>(depth)];
    // The paths that go on, in their order; where a first hit may branch, each one's continuations after it
    // (their rays, from one point, share packets), written to b.extras and copied back.
    std::uint16_t* next = depth == 0 && firstHitBranches_ > 1 ? b.extras.data() : b.live.data();
    std::size_t kept = 0, lit = 0, nextSlot = cameras;
    for (std::size_t i = 0; i < count; ++i) {
        const std::size_t k = b.live[i];
        SampleStream& samples = k < cameras ? streams[k] : b.branchStreams[k];
        PathContext pc{samples, stats, scratch};
        bool sampled = false;
        std::size_t branches = 0;
        // What fillAhead drew, for a path that reads ahead (the others have no slot this depth).
        VertexAhead drawn;
        if (ahead && readsAhead(b.paths[k], depth, settings_)) {
            const std::size_t slot = b.slot[k];
            drawn = VertexAhead{emittersAhead ? &b.emitterSamples[slot] : nullptr, b.emitterSampled[slot],
                                directionsAhead && b.materials[slot * calls] ? &b.draws[slot * calls] : nullptr};
        }
        const VertexStep step =
            advance(b.paths[k], terms[k], pc, drawn, b.shadowRays[lit], b.lights[lit], sampled, branches, b.spawned.data());
        if (sampled) b.lit[lit++] = static_cast<std::uint16_t>(k);
        if (step == VertexStep::Continues) next[kept++] = static_cast<std::uint16_t>(k);
        if (step != VertexStep::Branches) continue;
        // A branching first hit: its first continuation goes on in the camera sample's slot, the others in slots
        // of their own (past the camera samples': at most cameras x firstHitBranches() <= kSize in all).
        b.branched[k] = true;
        b.extraBegin[k] = static_cast<std::uint16_t>(nextSlot);
        for (std::size_t j = 0; j < branches; ++j) {
            const std::size_t s = j == 0 ? k : nextSlot++;
            const FirstHitBranch& f = b.spawned[j];
            WavePath& w = b.paths[s];  // each field set (its hit and `found` once its ray is traced): no zeroing first
            w.o = f.o, w.d = f.d, w.depth = 1, w.path = f.path, w.prevMisPdf = f.misPdf, w.throughput = f.throughput;
            terms[s].weight = f.weight;
            terms[s].survive = f.survive;
            next[kept++] = static_cast<std::uint16_t>(s);
            if (s == k) continue;
            terms[s].own = Color(0.0);
            b.branchStreams[s] = samples;
            if (ahead) {
                b.branchStreams[s].readAhead(&b.ahead[s]);
                b.keys[s] = b.keys[k];
                b.indices[s] = b.indices[k];
            }
        }
        b.extraEnd[k] = static_cast<std::uint16_t>(nextSlot);
    }
    // The depth's shadow rays together; a clear one's term joins its vertex's own (at the first hit weighed
    // against the estimator's --split k calls, as shade() weighs it).
    accel_.occludedEach(b.shadowRays.data(), lit, b.blocked.data());
    stats.rays += lit;
    const double misCalls = depth == 0 ? settings_.firstHitSplit : 1;  // shade()'s value(); k >= 1 (the constructor)
    for (std::size_t i = 0; i < lit; ++i)
        if (!b.blocked[i]) terms[b.lit[i]].own += litBy(b.lights[i]).value(misCalls);
    if (next != b.live.data()) std::copy_n(next, kept, b.live.begin());
    return kept;
}

void PathTracer::fillAhead(WavefrontBatch& b, std::size_t count, std::uint32_t spp, int depth) const {
    // The live paths whose vertex reads these dimensions.
    std::size_t m = 0;
    for (std::size_t i = 0; i < count; ++i)
        if (readsAhead(b.paths[b.live[i]], depth, settings_)) b.at[m++] = b.live[i];
    if (m == 0) return;
    // After a branching first hit, its continuations read their own paths' dimensions: ordered by path, runs of
    // one dimension for the lanes (b.live keeps each first hit's continuations together, for Embree's packets).
    if (depth > 0 && firstHitBranches_ > 1) {
        std::copy_n(b.at.begin(), m, b.extras.begin());
        groupByPath(b, b.extras.data(), m, b.at.data());
    }
    for (std::size_t i = 0; i < m; ++i) {
        const std::size_t k = b.at[i];
        b.slot[k] = static_cast<std::uint16_t>(i);
        b.atKeys[i] = b.keys[k];
        b.atIndices[i] = b.indices[k];
    }
    std::size_t runCount = 0;
    for (std::size_t i = 0; i < m; ++i)
        if (i == 0 || b.paths[b.at[i]].path != b.paths[b.at[i - 1]].path) b.runs[runCount++] = static_cast<std::uint16_t>(i);
    b.runs[runCount] = static_cast<std::uint16_t>(m);
    const auto values = [&](AheadSlot slot, auto dimOf) { valuesAhead(b, runCount, spp, slot, dimOf); };
    // advance()'s reads at this depth, at its dimensions: the light sample, the estimator's pair, the roulette.
    if (lightSampling_) {
        values(AheadSlot::LightPair, [&](std::uint64_t path) { return SampleDimensions::vertex(depth, path) + SampleDimensions::kLight; });
        // The emitters' samples from those pairs, at the points advance() will shade (its p: the same bits),
        // together: the untextured triangles' in vector lanes, and each sample's chain of square roots and
        // divisions overlapping the others' (docs/performance.md "The emitters' samples ahead"). A path that
        // ends before its light sample (wo below its surface) drew one for nothing.
        for (std::size_t i = 0; i < m; ++i) {
            const WavePath& w = b.paths[b.at[i]];
            b.points[i] = w.o + w.d * w.hit.t;
        }
        emitters_.sampleMany(b.points.data(), b.us.data(), b.vs.data(), m, b.emitterSamples.data(), b.emitterSampled.data());
    }
    // The estimator's pairs. A first hit under --split k reads k, on its sub-samples i k + j of a pattern of
    // spp x k (SampleStream::split): computed where the estimator draws ahead, path i's in k slots of its own
    // (i k + j; the batch holds them: m k <= kSize / firstHitBranches() x k).
    const std::size_t split = estimatorCalls(settings_, depth);
    if (split == 1) {
        values(AheadSlot::EstimatorPair, [&](std::uint64_t path) { return estimatorDimension(depth, path); });
    } else if (estimator_.drawsAhead(true)) {
        const auto k = static_cast<std::uint32_t>(split);
        for (std::size_t i = m; i-- > 0;) {  // from the last, so that each is read before the ones after it are written
            const std::uint64_t key = b.atKeys[i];
            const std::uint32_t index = b.atIndices[i];
            for (std::uint32_t j = 0; j < k; ++j) {
                b.atKeys[i * split + j] = key;
                b.atIndices[i * split + j] = SampleStream::subSampleIndex(index, j, k);
            }
        }
        sobolPairValues(b.atKeys.data(), b.atIndices.data(), SampleStream::subSampleCount(spp, k), estimatorDimension(0, 0), m * split,
                        b.us.data(), b.vs.data());
    }
    // The estimator's directions from those pairs, where it draws ahead and the vertex's material is its
    // triangle's (a textured one is known only at the vertex): like the emitter samples, a loop of chains that
    // overlap (a division, a square root, pow or the sine's polynomial).
    if (estimator_.drawsAhead(depth == 0)) {
        std::size_t drawable = 0;
        for (std::size_t i = 0; i < m; ++i) {
            const std::uint32_t material = scene_.triangles[b.paths[b.at[i]].hit.prim].material;
            const PhongMaterial* drawn = textured_[material] ? nullptr : &scene_.materials[material];
            for (std::size_t j = 0; j < split; ++j) b.materials[i * split + j] = drawn;
            drawable += drawn != nullptr;
        }
        if (drawable > 0) estimator_.drawAhead(b.materials.data(), b.us.data(), b.vs.data(), m * split, b.draws.data());
    }
    // The roulette (not for --split k's first hit: its continuations read theirs at their own paths' dimensions).
    if (depth + 1 >= settings_.rrDepth && split == 1)
        values(AheadSlot::Single,
               [&](std::uint64_t path) { return SampleDimensions::vertex(depth + 1, path) + SampleDimensions::kRoulette; });
}

}  // namespace symphong
