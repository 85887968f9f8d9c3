#include "lights/emitters.h"

#include "lights/kinds.h"

#include <algorithm>
#include <stdexcept>

namespace symphong {

namespace {

/// The table of light kinds: one entry per Light::Type.
struct LightKind {
    Light::Type type;
    std::unique_ptr<Emitter> (*create)(const Light&);
};

const LightKind kLightKinds[] = {
    {Light::Type::Point, makePointEmitter},
    {Light::Type::Spot, makeSpotEmitter},
    {Light::Type::Directional, makeDirectionalEmitter},
};

}  // namespace

std::unique_ptr<Emitter> makeLightEmitter(const Light& light) {
    for (const LightKind& k : kLightKinds)
        if (k.type == light.type) return k.create(light);
    throw std::logic_error("a light type without an emitter kind");
}

SceneEmitters::SceneEmitters(const Scene& scene, const std::vector<double>& areas, const std::vector<Vec3>& normals, bool withHittable)
    : triangleEmitter_(scene.triangles.size(), -1) {
    for (std::size_t i = 0; i < scene.triangles.size(); ++i)
        if (scene.materials[scene.triangles[i].material].isEmissive()) {
            triangleEmitter_[i] = static_cast<std::int32_t>(all_.size());
            all_.push_back(makeTriangleEmitter(scene, static_cast<std::uint32_t>(i), areas[i], normals[i]));
        }
    lightsBegin_ = all_.size();
    for (const Light& l : scene.lights) all_.push_back(makeLightEmitter(l));
    backgroundIndex_ = all_.size();
    all_.push_back(makeBackgroundEmitter(scene));

    Vec3 lo, hi;
    scene.bounds(lo, hi);
    const double radius = 0.5 * length(hi - lo);
    std::vector<double> power;
    slot_.assign(all_.size(), -1);
    for (std::size_t i = 0; i < all_.size(); ++i) {
        const Emitter& e = *all_[i];
        if (!withHittable && !e.isDelta()) continue;
        const double p = e.power(radius);
        if (!(p > 0)) continue;
        slot_[i] = static_cast<std::int64_t>(sampled_.size());
        sampled_.push_back(i);
        power.push_back(p);
        if (i < lightsBegin_) samplesTriangles_ = true;
        if (i == backgroundIndex_) backgroundSlot_ = slot_[i];
    }
    distribution_ = Distribution1D(power);
}

const Emitter& SceneEmitters::pick(double u, double& probability, double& uRemapped) const {
    const std::size_t i = distribution_.sample(u);
    probability = distribution_.pmf(i);
    uRemapped = std::clamp((u - distribution_.cdf(i)) / probability, 0.0, kOneBelow);
    return *all_[sampled_[i]];
}

std::vector<const Emitter*> SceneEmitters::lights() const {
    std::vector<const Emitter*> out;
    for (std::size_t i = lightsBegin_; i < backgroundIndex_; ++i) out.push_back(all_[i].get());
    return out;
}

}  // namespace symphong
