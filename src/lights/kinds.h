// lights/kinds.h — the emitter kinds' factories, one file each (triangle_emitter.cpp: a plain row, not an
// Emitter; point_light.cpp,
// spot_light.cpp, directional_light.cpp, backgrounds.cpp); lights/emitters.cpp's table maps the scene's
// light types to them.
#pragma once

#include "lights/emitter.h"
#include "scene/scene.h"

#include <memory>

namespace symphong {

/// One emissive triangle as light sampling sees it: plain values, one row of SceneEmitters' table (no
/// object of its own). A uniform point q on it (sampleUniformTriangle), density in solid angle at p
///   p(wi) = pick / area x d^2 / cos(theta_L)
/// (d = |q - p|, theta_L the angle at q between its normal and -wi); the emission Ke, or Ke x its
/// texture at q, where a cut-out makes a hole.
struct TriangleLight {
    Vec3 v0, v1, v2;  ///< the corners
    Vec3 normal;      ///< unit geometric normal (counter-clockwise winding)
    double area = 0;
    double pick = 1;          ///< the probability that light sampling picks it
    double pickOverArea = 0;  ///< pick / area
    Color emission;           ///< Ke
    std::uint32_t prim = 0;   ///< its index in Scene::triangles
    bool textured = false;    ///< its material has textures (the emission and cut-outs are looked up)
};
/// Emissive triangle `prim` of the scene (area and unit geometric normal given), picked with probability 1.
TriangleLight makeTriangleLight(const Scene& scene, std::uint32_t prim, double area, const Vec3& normal);
/// Its luminance power area x Y(Ke), for choosing among emitters.
inline double trianglePower(const TriangleLight& t) { return t.area * luminance(t.emission); }
/// A direction from p towards a uniform point of the triangle from u (the density includes the pick);
/// false when it brings nothing (p behind it, a cut-out).
bool sampleTriangleLight(const TriangleLight& t, const Scene& scene, const Vec3& p, Point2 u, EmitterSample& s);
/// The density sampleTriangleLight gives direction d along which a path reached the triangle after t (t |d| the distance).
inline double triangleLightPdfOfHit(const TriangleLight& tri, const Vec3& d, double t) {
    const double dist2 = t * t * dot(d, d);
    const double cosL = -dot(tri.normal, d) / length(d);
    return tri.pickOverArea * dist2 / cosL;
}
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
