// A packet's paths depth by depth (PathTracer's members for it; the recursive tracer is in path_tracer.cpp):
// every path of a packet of camera rays takes its vertex at depth d before any takes its vertex at d + 1,
// each vertex adding its emission and light sample to the path's sum times the path's throughput and
// handing on the next ray, instead of shade() calling itself for the next vertex and adding on the way
// back. The first step of a wavefront tracer (docs/performance.md "The second tracer"): the same
// decisions at the same sample dimensions as the recursive tracer, so the same paths; each sum equal to
// shade()'s up to the rounding of its order (forward here, from the deepest vertex there).
#include "math/frame.h"
#include "render/path_tracer.h"
#include "scene/shading_normal.h"
#include "scene/surface.h"

#include <algorithm>

namespace symphong {

// shade() and continuePath() for one continuation a vertex (tracesAsWavefront): their code in their order,
// with the continuation handed back in `w` instead of traced.
bool PathTracer::advance(WavePath& w, PathContext& pc) const {
    const int depth = w.depth;
    if (!w.found) {
        Color emitted;
        w.L += w.throughput * escaped(w.d, depth, w.prevMisPdf, emitted);
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
    // The vertex's terms, into the path's sum at its throughput; the path ends here unless it continues below.
    const auto end = [&] {
        w.L += w.throughput * L;
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
        samples.setDimension(SampleDimensions::vertex(depth, 0) + SampleDimensions::kLight);
        L += directLight(p, ng, frame, sc, samples.get2D(), pc.stats, shadowed).value(1);
    }
    DirectionList& dirs = pc.scratch.directions[static_cast<std::size_t>(depth)];
    dirs.clear();
    samples.setDimension(depth == 0 ? SampleDimensions::firstHitEstimator(settings_.firstBounceStream)
                                    : SampleDimensions::vertex(depth, 0) + SampleDimensions::kEstimator);
    estimator_.sample(sc, samples, dirs);
    if (dirs.empty()) return end();
    const DirectionSample& s = dirs[0];
    const Vec3 wi = frame.toWorld(s.wi);
    if (s.wi.z <= 0 || dot(wi, ng) <= 0) return end();  // below the surface: no light comes through it
    const Color weight = shadowed ? s.weight * bumpShadowing(ng, frame.n, wi) : s.weight;
    Color next = w.throughput * weight;  // continuePath's throughput x weight x branches: one branch, x 1 exactly
    if (depth + 1 >= settings_.rrDepth) {
        const double survive = std::min(0.95, maxComponent(next));
        samples.setDimension(SampleDimensions::vertex(depth + 1, 0) + SampleDimensions::kRoulette);
        if (!(survive > 0) || samples.get1D() >= survive) return end();
        next /= survive;
    }
    w.L += w.throughput * L;
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
    n = std::min(n, kCameraPacket);
    std::array<Hit, kCameraPacket> hits;
    std::array<bool, kCameraPacket> found;
    accel_.intersectBundle(o, dirs, n, 0.0, hits.data(), found.data(), true);
    stats.rays += n;
    std::array<WavePath, kCameraPacket> paths;
    std::array<std::uint8_t, kCameraPacket> live;  // the paths still going, in the packet's order
    for (std::size_t k = 0; k < n; ++k) {
        paths[k].o = o;
        paths[k].d = dirs[k];
        paths[k].hit = hits[k];
        paths[k].found = found[k];
        live[k] = static_cast<std::uint8_t>(k);
    }
    for (std::size_t count = n; count > 0;) {
        std::size_t kept = 0;
        for (std::size_t i = 0; i < count; ++i) {
            const std::size_t k = live[i];
            PathContext pc{streams[k], stats, scratch};
            if (advance(paths[k], pc)) live[kept++] = static_cast<std::uint8_t>(k);
        }
        count = kept;
        std::array<Vec3, kCameraPacket> origins, directions;
        for (std::size_t i = 0; i < count; ++i) {
            origins[i] = paths[live[i]].o;
            directions[i] = paths[live[i]].d;
        }
        accel_.intersectEach(origins.data(), directions.data(), count, epsilon_, hits.data(), found.data());
        stats.rays += count;
        for (std::size_t i = 0; i < count; ++i) {
            paths[live[i]].hit = hits[i];
            paths[live[i]].found = found[i];
        }
    }
    for (std::size_t k = 0; k < n; ++k) out[k] = paths[k].L;
}

}  // namespace symphong
