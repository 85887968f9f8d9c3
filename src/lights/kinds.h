// lights/kinds.h — the emitter kinds' factories, one file each (triangle_emitter.cpp, point_light.cpp,
// spot_light.cpp, directional_light.cpp, backgrounds.cpp); lights/emitters.cpp's table maps the scene's
// light types to them.
#pragma once

#include "lights/emitter.h"
#include "scene/scene.h"

#include <memory>

namespace symphong {

/// Emissive triangle `prim` of the scene (area and unit geometric normal given): a uniform point on it.
std::unique_ptr<Emitter> makeTriangleEmitter(const Scene& scene, std::uint32_t prim, double area, const Vec3& normal);
/// A point light: intensity I in every direction.
std::unique_ptr<Emitter> makePointEmitter(const Light& light);
/// What arrives at p from a point source of intensity I (a point or spot light): the direction to it,
/// I / d^2, the density `pick` (a delta emitter) and the shadow ray's end; false when p is at the light.
bool samplePointSource(const Light& light, const Vec3& p, double pick, EmitterSample& s);
/// A spot light: a point light within a cone, smoothstep falloff between its inner and outer angles.
std::unique_ptr<Emitter> makeSpotEmitter(const Light& light);
/// A directional light: irradiance E arriving along one direction.
std::unique_ptr<Emitter> makeDirectionalEmitter(const Light& light);
/// The background of rays that leave the scene: its environment map (importance-sampled), its default
/// sky or its constant environment (neither sampled: seen only by paths).
std::unique_ptr<Emitter> makeBackgroundEmitter(const Scene& scene);

/// "(x, y, z)" with 6 significant digits, as `symphong info` prints vectors.
std::string formatTriple(const Vec3& v);

}  // namespace symphong
