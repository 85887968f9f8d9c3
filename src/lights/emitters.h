// lights/emitters.h — a scene's emitters and the choice among them for light sampling: every emissive
// triangle (rows of one flat table, lights/kinds.h TriangleLight), every light of Scene::lights (through
// the table of kinds in emitters.cpp) and the background, built once per render; light sampling picks
// one in proportion to its power from an alias table (constant time, sampling/alias_table.h).
#pragma once

#include "lights/emitter.h"
#include "lights/kinds.h"
#include "sampling/alias_table.h"
#include "scene/scene.h"

#include <cstdint>
#include <memory>
#include <vector>

namespace symphong {

/// The emitter of one of the scene's lights, made by the table entry of its type.
std::unique_ptr<Emitter> makeLightEmitter(const Light& light);

class SceneEmitters {
public:
    /// areas and normals: of every triangle (unit geometric normals). withHittable: whether the emitters
    /// a path can also hit (triangles, the environment map) are light-sampled; delta emitters always are,
    /// since nothing else reaches them. `scene` must outlive this (textured emitters read it).
    SceneEmitters(const Scene& scene, const std::vector<double>& areas, const std::vector<Vec3>& normals, bool withHittable);

    /// Nothing to light-sample.
    bool empty() const { return entries_.empty(); }
    /// Whether some emissive triangle is light-sampled (MIS applies to paths that hit one).
    bool samplesTriangles() const { return samplesTriangles_; }
    /// Whether the background is light-sampled (MIS applies to paths that leave the scene).
    bool samplesBackground() const { return backgroundEntry_ >= 0; }

    /// Light sampling at p: an emitter chosen in proportion to its power from u.u (the probability is in
    /// s.pdf), then a direction towards it from u.u rescaled inside the emitter's share and u.v; s.delta
    /// for a point or a direction, s.radianceLater for the background (background().backgroundRadiance).
    /// False when it brings nothing (facing away, zero density, a cut-out).
    bool sample(const Vec3& p, Point2 u, EmitterSample& s) const {
        double uRemapped = 0;
        const std::size_t entry = table_.sample(u.u, uRemapped);
        return sampleEntry(entry, p, {uRemapped, u.v}, s);
    }
    /// sampled[i] = sample(ps[i], {us[i], vs[i]}, out[i]), i < n: the same samples, the untextured triangles'
    /// in the vector lanes of lights/triangle_lanes.h (the wavefront tracer's light samples of a depth).
    void sampleMany(const Vec3* ps, const double* us, const double* vs, std::size_t n, EmitterSample* out, bool* sampled) const;
    /// The density light sampling gives direction d along which a path hit triangle `prim` after t (t |d|
    /// the distance); 0 for a triangle it does not sample.
    double trianglePdfOfHit(std::uint32_t prim, const Vec3& d, double t) const {
        const std::int32_t i = triangleRow_[prim];
        return i < 0 ? 0.0 : triangleLightPdfOfHit(triangles_[static_cast<std::size_t>(i)], d, t);
    }
    /// Whether triangle `prim` emits (its material's Ke is not black).
    bool emits(std::uint32_t prim) const { return triangleRow_[prim] >= 0; }
    /// Probability that light sampling picks triangle `prim` (0 when it is not sampled).
    double triangleProbability(std::uint32_t prim) const {
        const std::int32_t i = triangleRow_[prim];
        return i < 0 ? 0.0 : triangles_[static_cast<std::size_t>(i)].pick;
    }
    const Emitter& background() const { return *others_.back(); }
    /// Probability that light sampling picks the background.
    double backgroundProbability() const { return backgroundEntry_ < 0 ? 0.0 : table_.pmf(static_cast<std::size_t>(backgroundEntry_)); }

    /// The emitters of Scene::lights, in order (for `symphong info`).
    std::vector<const Emitter*> lights() const;

private:
    /// sample() once the table chose `entry`, u.u rescaled inside its share.
    bool sampleEntry(std::size_t entry, const Vec3& p, Point2 u, EmitterSample& s) const {
        const std::int32_t i = entries_[entry];
        if (i >= 0) return sampleTriangleLight(triangles_[static_cast<std::size_t>(i)], scene_, p, u, s);
        const Emitter& e = *others_[static_cast<std::size_t>(-1 - i)];
        if (!e.sample(p, u, table_.pmf(entry), s)) return false;
        s.delta = e.isDelta();
        return true;
    }
    const Scene& scene_;
    std::vector<TriangleLight> triangles_;          ///< the emissive triangles
    std::vector<std::int32_t> triangleRow_;         ///< triangle -> its row in triangles_, or -1
    std::vector<std::unique_ptr<Emitter>> others_;  ///< Scene::lights' emitters, then the background
    std::vector<std::int32_t> entries_;             ///< the sampled: a row of triangles_ (>= 0) or -1 - an index of others_
    std::int64_t backgroundEntry_ = -1;
    bool samplesTriangles_ = false;
    AliasTable table_;
};

}  // namespace symphong
