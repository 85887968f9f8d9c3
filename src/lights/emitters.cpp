#include "lights/emitters.h"

#include "lights/triangle_lanes.h"

#include <algorithm>
#include <array>
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
    : scene_(scene), triangleRow_(scene.triangles.size(), -1) {
    for (std::size_t i = 0; i < scene.triangles.size(); ++i)
        if (scene.materials[scene.triangles[i].material].isEmissive()) {
            triangleRow_[i] = static_cast<std::int32_t>(triangles_.size());
            triangles_.push_back(makeTriangleLight(scene, static_cast<std::uint32_t>(i), areas[i], normals[i]));
        }
    for (const Light& l : scene.lights) others_.push_back(makeLightEmitter(l));
    others_.push_back(makeBackgroundEmitter(scene));

    Vec3 lo, hi;
    scene.bounds(lo, hi);
    const double radius = 0.5 * length(hi - lo);
    std::vector<double> power;
    if (withHittable)
        for (std::size_t i = 0; i < triangles_.size(); ++i) {
            const double p = trianglePower(triangles_[i]);
            if (!(p > 0)) continue;
            entries_.push_back(static_cast<std::int32_t>(i));
            power.push_back(p);
            samplesTriangles_ = true;
        }
    for (std::size_t i = 0; i < others_.size(); ++i) {
        const Emitter& e = *others_[i];
        if (!withHittable && !e.isDelta()) continue;
        const double p = e.power(radius);
        if (!(p > 0)) continue;
        if (i + 1 == others_.size()) backgroundEntry_ = static_cast<std::int64_t>(entries_.size());
        entries_.push_back(-1 - static_cast<std::int32_t>(i));
        power.push_back(p);
    }
    table_ = AliasTable(power);
    // A triangle's density includes the probability of picking it; one light sampling never picks has none.
    for (TriangleLight& t : triangles_) t.pick = t.pickOverArea = 0;
    for (std::size_t e = 0; e < entries_.size(); ++e)
        if (entries_[e] >= 0) {
            TriangleLight& t = triangles_[static_cast<std::size_t>(entries_[e])];
            t.pick = table_.pmf(e);
            t.pickOverArea = t.pick / t.area;
        }
}

std::vector<const Emitter*> SceneEmitters::lights() const {
    std::vector<const Emitter*> out;
    for (std::size_t i = 0; i + 1 < others_.size(); ++i) out.push_back(others_[i].get());
    return out;
}

void SceneEmitters::sampleMany(const Vec3* ps, const double* us, const double* vs, std::size_t n, EmitterSample* out, bool* sampled) const {
    // A chunk at a time: the emitters picked one by one, the untextured triangles' samples gathered for the lanes
    // and put back in their places.
    constexpr std::size_t kChunk = 64;
    std::array<std::uint32_t, kChunk> rows;
    std::array<Vec3, kChunk> points;
    std::array<double, kChunk> lightU, lightV;
    std::array<std::size_t, kChunk> at;
    union Samples {  // left uninitialised (its constructor sets nothing): only the samples drawn are read from it
        Samples() {}
        EmitterSample at[kChunk];
    } samples;
    std::array<bool, kChunk> ok;
    for (std::size_t first = 0; first < n; first += kChunk) {
        const std::size_t end = std::min(n, first + kChunk);
        std::size_t m = 0;
        for (std::size_t i = first; i < end; ++i) {
            double uRemapped = 0;
            const std::size_t entry = table_.sample(us[i], uRemapped);
            const std::int32_t row = entries_[entry];
            if (row >= 0 && static_cast<std::size_t>(row) < kTriangleLaneRows && !triangles_[static_cast<std::size_t>(row)].textured) {
                rows[m] = static_cast<std::uint32_t>(row);
                points[m] = ps[i];
                lightU[m] = uRemapped;
                lightV[m] = vs[i];
                at[m++] = i;
            } else {
                sampled[i] = sampleEntry(entry, ps[i], {uRemapped, vs[i]}, out[i]);
            }
        }
        sampleTriangleLights(triangles_.data(), rows.data(), scene_, points.data(), lightU.data(), lightV.data(), m, samples.at, ok.data());
        for (std::size_t j = 0; j < m; ++j) {
            if (ok[j]) out[at[j]] = samples.at[j];
            sampled[at[j]] = ok[j];
        }
    }
}

}  // namespace symphong
