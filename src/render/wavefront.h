// render/wavefront.h — the state of the wavefront tracer (PathTracer::tracesAsWavefront, render/wavefront.cpp):
// a batch of camera samples' paths kept between depths, each path's ray, what it found, its throughput and the
// terms of its vertices so far; the live paths' indices; the arrays that the batched stages hand to Embree (the continuing rays)
// and to the sampler's lanes (the pixel keys and sample indices, the values computed ahead). One a thread, in
// its PathScratch, allocated once.
#pragma once

#include "accel/accel.h"
#include "estimators/estimator.h"
#include "lights/emitter.h"
#include "math/vec3.h"
#include "render/direct_light.h"
#include "sampling/sampler.h"

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace symphong {

/// A path of the wavefront: the ray that reached its next vertex and what it found.
struct WavePath {
    Vec3 o, d;
    Hit hit;
    bool found = false;
    int depth = 0;
    std::uint64_t path = 0;  ///< its dimensions' path (SampleDimensions::vertex): 0, or branch j + 1 of a branching first hit
    double prevMisPdf = 0;
    Color throughput{1.0};  ///< shade()'s throughput: the product of the weights / survival probabilities so far
};

/// A vertex's part of its path's radiance: its own terms (emission, then the light sample: `own`, shade()'s L
/// before its continuation), and how the rest of the path enters (weight x rest / survive). The path's
/// radiance is summed from its last vertex back to its first, own + (weight x rest) / survive at each, in
/// shade()'s order of operations: the recursive tracer's value bit for bit.
struct VertexTerms {
    Color own{0.0};
    Color weight{0.0};
    double survive = 1.0;
};

/// What fillAhead drew for one vertex before advance() takes it (nullptr: drawn there, as the recursive tracer
/// draws it): its emitter sample with SceneEmitters::sample's answer, and its estimator's direction.
struct VertexAhead {
    const EmitterSample* emitter = nullptr;
    bool emitterSampled = false;
    const DirectionDraw* direction = nullptr;
};

/// What became of a path at its vertex (PathTracer::advance): it ends there, it goes on (one continuation), or
/// its first hit branches (a set, or --split k: its continuations in slots of their own, WavefrontBatch::spawned).
enum class VertexStep { Ends, Continues, Branches };

/// A continuation of a branching first hit (a set estimator's directions, or --split k's): its ray, its path's
/// dimensions, its throughput past the roulette, and how its radiance enters the first hit's (weight / survive).
struct FirstHitBranch {
    Vec3 o, d;
    double misPdf = 0;
    Color throughput{0.0};
    Color weight{0.0};
    double survive = 1.0;
    std::uint64_t path = 0;
};

/// The wavefront's batch: up to kSize camera samples traced together, depth by depth.
struct WavefrontBatch {
    /// Paths a batch holds: its camera samples' (render/renderer.cpp gathers them), enough that the stages' loops
    /// and the sampler's lanes run full at the deeper depths, where few of the paths are left; where a first hit
    /// branches (PathTracer::firstHitBranches() > 1) it takes kSize / that many camera samples, and each further
    /// continuation takes a slot past theirs.
    static constexpr std::size_t kSize = 256;
    std::array<WavePath, kSize> paths;
    std::vector<std::array<VertexTerms, kSize>> terms;  ///< terms[d][k]: path k's vertex at depth d (grown as depths are reached)
    std::array<std::uint16_t, kSize> live;              ///< the paths still going, in the batch's order
    std::array<Hit, kSize> hits;
    std::array<bool, kSize> found;
    std::array<Vec3, kSize> origins, directions;  ///< the continuing rays, for Accel::intersectEach
    // A depth's light samples, their shadow rays traced together after the depth's vertices (Accel::occludedEach).
    std::array<ShadowRay, kSize> shadowRays;
    std::array<LightSample, kSize> lights;
    std::array<std::uint16_t, kSize> lit;  ///< the path of each
    std::array<bool, kSize> blocked;
    // The sampler's values computed ahead (PathTracer::fillAhead): the paths at a surface, their keys and
    // indices, the values that their streams read (SampleStream::readAhead), the lanes' output.
    std::array<std::uint64_t, kSize> keys;       ///< path k's pixel key
    std::array<std::uint32_t, kSize> indices;    ///< path k's sample index
    std::array<std::uint16_t, kSize> at;         ///< the paths at a surface (fillAhead)
    std::array<std::uint16_t, kSize> slot;       ///< path k's place among them: its index in `at` and in the arrays below
    std::array<std::uint64_t, kSize> atKeys;     ///< their keys
    std::array<std::uint32_t, kSize> atIndices;  ///< their sample indices
    std::array<AheadValues, kSize> ahead;
    std::array<double, kSize> us, vs;
    /// The emitters' samples of the paths at a surface (in their slots), drawn ahead of their vertices from the
    /// light pairs computed ahead (PathTracer::fillAhead): the points, SceneEmitters::sampleMany's output and answers.
    std::array<Vec3, kSize> points;
    std::array<EmitterSample, kSize> emitterSamples;
    std::array<bool, kSize> emitterSampled;
    /// The estimator's directions drawn ahead from the estimator's pairs (Estimator::drawAhead), for the paths at a
    /// surface whose material is known before its vertex (not textured; the others' material null), in their slots.
    std::array<const PhongMaterial*, kSize> materials;
    std::array<DirectionDraw, kSize> draws;
    /// A branching first hit: camera sample c's vertex branched (branched[c]); its first continuation goes on in
    /// its own slot c, the others in slots extraBegin[c]..extraEnd[c] - 1 (past the camera samples), each with a
    /// copy of c's stream (branchStreams[slot]); spawned: one vertex's continuations (PathTracer::spawnBranches).
    std::array<bool, kSize> branched;
    std::array<std::uint16_t, kSize> extraBegin, extraEnd;
    std::array<SampleStream, kSize> branchStreams;
    std::array<FirstHitBranch, kSize> spawned;
    std::array<std::uint16_t, kSize> extras;  ///< scratch: the paths going on from a depth that may branch; fillAhead's sort
    /// fillAhead: where each run of paths at a surface that share a path (their dimensions) begins in `at`.
    std::array<std::uint16_t, kSize + 1> runs;
};

}  // namespace symphong
