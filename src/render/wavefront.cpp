// A batch of camera samples' paths depth by depth (PathTracer's members for it; the recursive tracer is in
// path_tracer.cpp; the batch's state in wavefront.h): every path of the batch takes its vertex at depth d before any
// takes its vertex at d + 1, each vertex keeping its terms (VertexTerms) and handing on the next ray, instead of
// shade() calling itself for the next vertex and adding on the way back; a depth's shadow rays, then its
// continuing rays, go to Embree together (Accel::occludedEach one by one, intersectEach in 16-wide packets), and the sampler's
// values of a depth's vertices are computed together in vector lanes (sobol_lanes.h), and from them the vertices'
// light samples and estimator directions (fillAhead: lanes too, where they run). The same decisions at the
// same sample dimensions as the recursive tracer, so the same paths, and each path's terms summed at its end from
// the last vertex back, in shade()'s order: the same radiance bit for bit where Embree answers each query as the
// single-ray one does (an Accel without packets); with packets, the same but for the rare grazing ray that a
// packet's kernels round otherwise (docs/performance.md "The second tracer", "Shadow and bounce rays in packets").
#include "math/frame.h"
#include "render/next_event.h"
#include "render/path_tracer.h"
#include "sampling/sobol_lanes.h"
#include "scene/shading_normal.h"
#include "scene/surface.h"

#include <algorithm>

namespace symphong {

namespace {

/// A vertex's directions: from its draw where fillAhead drew it ahead, else sampled from its stream at `dim`.
void sampleVertex(const Estimator& estimator, const ShadingContext& sc, const DirectionDraw* drawn, SampleStream& samples,
                  std::uint64_t dim, DirectionList& dirs) {
    if (drawn) {
        estimator.sampleDrawn(sc, *drawn, dirs);
    } else {
        samples.setDimension(dim);
        estimator.sample(sc, samples, dirs);
    }
}

}  // namespace

std::uint64_t PathTracer::estimatorDimension(int depth) const {
    return depth == 0 ? SampleDimensions::firstHitEstimator(settings_.firstBounceStream)
                      : SampleDimensions::vertex(depth, 0) + SampleDimensions::kEstimator;
}

// shade() and continuePath() for one continuation a vertex (tracesAsWavefront): their code in their order,
// with the continuation handed back in `w` instead of traced.
bool PathTracer::advance(WavePath& w, VertexTerms& terms, PathContext& pc, const VertexAhead& ahead, ShadowRay& shadow, LightSample& light,
                         bool& lit) const {
    const int depth = w.depth;
    if (!w.found) {
        Color emitted;
        terms.own = escaped(w.d, depth, w.prevMisPdf, emitted);
        return false;
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
        return false;
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
    if (lightSampling_) {
        // directLight up to its shadow ray, which the depth's loop traces with the others (its term is
        // added to `own` then: shadow's L += value(1), after the emission, in its order).
        if (ahead.emitter) {
            lit = lightSampleOf(ahead.emitterSampled, *ahead.emitter, p, ng, frame, sc, shadowed, shadow, light);
        } else {
            samples.setDimension(SampleDimensions::vertex(depth, 0) + SampleDimensions::kLight);
            lit = lightSample(p, ng, frame, sc, samples.get2D(), shadowed, shadow, light);
        }
        if (lit && !light.light.delta) light.light.estimatorPdf = estimator_.misPdf(sc, light.wiLocal);  // sc's material: this vertex's
    }
    DirectionList& dirs = pc.scratch.directions[static_cast<std::size_t>(depth)];
    dirs.clear();
    sampleVertex(estimator_, sc, ahead.direction, samples, estimatorDimension(depth), dirs);
    if (dirs.empty()) return end();
    const DirectionSample& s = dirs[0];
    const Vec3 wi = frame.toWorld(s.wi);
    if (s.wi.z <= 0 || dot(wi, ng) <= 0) return end();  // below the surface: no light comes through it
    const Color weight = shadowed ? s.weight * bumpShadowing(ng, frame.n, wi) : s.weight;
    Color next = w.throughput * weight;  // continuePath's throughput x weight x branches: one branch, x 1 exactly
    double survive = 1.0;
    if (depth + 1 >= settings_.rrDepth) {
        survive = std::min(0.95, maxComponent(next));
        samples.setDimension(SampleDimensions::vertex(depth + 1, 0) + SampleDimensions::kRoulette);
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
    return true;
}

void PathTracer::cameraRadiancesWavefront(const Vec3& o, const Vec3* dirs, std::size_t n, SampleStream* streams, Color* out,
                                          TraceStats& stats, PathScratch& scratch) const {
    prepare(scratch);
    if (scratch.wavefront.empty()) scratch.wavefront.resize(1);
    WavefrontBatch& b = scratch.wavefront.front();
    n = std::min(n, WavefrontBatch::kSize);
    // The camera rays as Embree packets (cameraRadiances' coherent packets of kCameraPacket).
    for (std::size_t first = 0; first < n; first += kCameraPacket) {
        const std::size_t m = std::min(kCameraPacket, n - first);
        accel_.intersectBundle(o, dirs + first, m, 0.0, b.hits.data() + first, b.found.data() + first, true);
    }
    stats.rays += n;
    for (std::size_t k = 0; k < n; ++k) {
        b.paths[k] = WavePath{};
        b.paths[k].o = o;
        b.paths[k].d = dirs[k];
        b.paths[k].hit = b.hits[k];
        b.paths[k].found = b.found[k];
        b.live[k] = static_cast<std::uint16_t>(k);
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
    // Where the values are computed ahead, so are the emitter samples, for every path that reaches its light sample.
    const bool emittersAhead = ahead && lightSampling_;
    const bool directionsAhead = ahead && estimator_.drawsAhead();
    for (std::size_t count = n, depth = 0; count > 0; ++depth) {
        if (ahead) fillAhead(b, count, spp, static_cast<int>(depth));
        if (b.terms.size() <= depth) b.terms.resize(depth + 1);
        auto& terms = b.terms[depth];
        std::size_t kept = 0, lit = 0;
        for (std::size_t i = 0; i < count; ++i) {
            const std::size_t k = b.live[i];
            PathContext pc{streams[k], stats, scratch};
            bool sampled = false;
            const std::size_t slot = b.slot[k];
            const VertexAhead drawn{emittersAhead ? &b.emitterSamples[slot] : nullptr, b.emitterSampled[slot],
                                    directionsAhead && b.materials[slot] ? &b.draws[slot] : nullptr};
            if (advance(b.paths[k], terms[k], pc, drawn, b.shadowRays[lit], b.lights[lit], sampled))
                b.live[kept++] = static_cast<std::uint16_t>(k);
            if (sampled) b.lit[lit++] = static_cast<std::uint16_t>(k);
        }
        // The depth's shadow rays together; a clear one's term joins its vertex's own.
        accel_.occludedEach(b.shadowRays.data(), lit, b.blocked.data());
        stats.rays += lit;
        for (std::size_t i = 0; i < lit; ++i)
            if (!b.blocked[i]) terms[b.lit[i]].own += litBy(b.lights[i]).value(1);
        count = kept;
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
    // Each path's radiance from its last vertex back to its first, as shade()'s returns add it up.
    for (std::size_t k = 0; k < n; ++k) {
        std::size_t d = static_cast<std::size_t>(b.paths[k].depth);
        Color L = b.terms[d][k].own;
        while (d-- > 0) {
            const VertexTerms& t = b.terms[d][k];
            L = t.own + t.weight * L / t.survive;
        }
        out[k] = L;
    }
}

void PathTracer::fillAhead(WavefrontBatch& b, std::size_t count, std::uint32_t spp, int depth) const {
    // The live paths at a surface below the depth limit: the ones whose vertex reads these dimensions.
    std::size_t m = 0;
    if (depth < settings_.maxDepth)
        for (std::size_t i = 0; i < count; ++i) {
            const std::size_t k = b.live[i];
            if (!b.paths[k].found) continue;
            b.at[m] = static_cast<std::uint16_t>(k);
            b.slot[k] = static_cast<std::uint16_t>(m);
            b.atKeys[m] = b.keys[k];
            b.atIndices[m] = b.indices[k];
            ++m;
        }
    if (m == 0) return;
    const auto pairs = [&](int slot, std::uint64_t dim) {
        sobolPairValues(b.atKeys.data(), b.atIndices.data(), spp, dim, m, b.us.data(), b.vs.data());
        for (std::size_t i = 0; i < m; ++i) {
            AheadValues& a = b.ahead[b.at[i]];
            a.pairDims[slot] = dim;
            a.pairs[slot] = {b.us[i], b.vs[i]};
        }
    };
    // advance()'s reads at this depth, at its dimensions: the light sample, the estimator's pair, the roulette.
    if (lightSampling_) {
        pairs(0, SampleDimensions::vertex(depth, 0) + SampleDimensions::kLight);
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
    pairs(1, estimatorDimension(depth));
    // The estimator's directions from those pairs, where it draws ahead and the vertex's material is its
    // triangle's (a textured one is known only at the vertex): like the emitter samples, a loop of chains that
    // overlap (a division, a square root, pow or the sine's polynomial).
    if (estimator_.drawsAhead()) {
        std::size_t drawable = 0;
        for (std::size_t i = 0; i < m; ++i) {
            const std::uint32_t material = scene_.triangles[b.paths[b.at[i]].hit.prim].material;
            b.materials[i] = textured_[material] ? nullptr : &scene_.materials[material];
            drawable += b.materials[i] != nullptr;
        }
        if (drawable > 0) estimator_.drawAhead(b.materials.data(), b.us.data(), b.vs.data(), m, b.draws.data());
    }
    if (depth + 1 >= settings_.rrDepth) {
        const std::uint64_t dim = SampleDimensions::vertex(depth + 1, 0) + SampleDimensions::kRoulette;
        sobolSingleValues(b.atKeys.data(), b.atIndices.data(), spp, dim, m, b.us.data());
        for (std::size_t i = 0; i < m; ++i) {
            AheadValues& a = b.ahead[b.at[i]];
            a.singleDim = dim;
            a.single = b.us[i];
        }
    }
}

}  // namespace symphong
