// lights/emitters.h — a scene's emitters and the choice among them for light sampling: every emissive
// triangle, every light of Scene::lights (through the table of kinds in emitters.cpp) and the
// background, built once per render; light sampling picks one in proportion to its power.
#pragma once

#include "lights/emitter.h"
#include "sampling/distribution1d.h"
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
    /// since nothing else reaches them.
    SceneEmitters(const Scene& scene, const std::vector<double>& areas, const std::vector<Vec3>& normals, bool withHittable);

    /// Nothing to light-sample.
    bool empty() const { return sampled_.empty(); }
    /// Whether some emissive triangle is light-sampled (MIS applies to paths that hit one).
    bool samplesTriangles() const { return samplesTriangles_; }
    /// Whether the background is light-sampled (MIS applies to paths that leave the scene).
    bool samplesBackground() const { return backgroundSlot_ >= 0; }

    /// The emitter of triangle `prim`, or nullptr when its material does not emit.
    const Emitter* triangle(std::uint32_t prim) const {
        const std::int32_t i = triangleEmitter_[prim];
        return i < 0 ? nullptr : all_[static_cast<std::size_t>(i)].get();
    }
    /// Probability that light sampling picks triangle `prim` (0 when it is not sampled).
    double triangleProbability(std::uint32_t prim) const {
        const std::int32_t i = triangleEmitter_[prim];
        return i < 0 ? 0.0 : probability(static_cast<std::size_t>(i));
    }
    const Emitter& background() const { return *all_[backgroundIndex_]; }
    /// Probability that light sampling picks the background.
    double backgroundProbability() const { return probability(backgroundIndex_); }

    /// Picks an emitter from u in [0,1): its probability, and u rescaled to [0,1) inside the chosen
    /// one's share (so one 2D value can choose an emitter and, with its rescaled u, a point on it).
    const Emitter& pick(double u, double& probability, double& uRemapped) const;

    /// The emitters of Scene::lights, in order (for `symphong info`).
    std::vector<const Emitter*> lights() const;

private:
    double probability(std::size_t emitter) const {
        const std::int64_t s = slot_[emitter];
        return s < 0 ? 0.0 : distribution_.pmf(static_cast<std::size_t>(s));
    }

    std::vector<std::unique_ptr<Emitter>> all_;  ///< emissive triangles, then lights, then the background
    std::vector<std::int64_t> slot_;             ///< emitter -> its entry in the distribution, or -1
    std::vector<std::size_t> sampled_;           ///< distribution entry -> emitter
    std::vector<std::int32_t> triangleEmitter_;  ///< triangle -> emitter, or -1
    std::size_t lightsBegin_ = 0, backgroundIndex_ = 0;
    std::int64_t backgroundSlot_ = -1;
    bool samplesTriangles_ = false;
    Distribution1D distribution_;
};

}  // namespace symphong
