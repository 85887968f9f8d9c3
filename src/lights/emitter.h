// lights/ — everything that emits light: emissive triangles (a JSON quad light is two of them) as rows
// of one flat table (lights/kinds.h TriangleLight, no object each), and behind one interface point,
// spot and directional lights, the environment map, the default sky and the constant environment. Each
// emitter samples a direction towards itself from a shading point with its density, gives the density
// of a direction along which a path found it, its power for choosing among emitters, and whether it is
// a delta emitter (a point or a direction, which no path can hit). The path tracer's one
// direct-lighting routine and its MIS weights (render/path_tracer.cpp) go through SceneEmitters only
// (lights/emitters.h: the table, the other emitters from the table of kinds, the alias table that
// chooses among them).
// Emitters read the scene (scene/) and never trace rays: the caller tests the shadow ray.
#pragma once

#include "math/vec3.h"
#include "sampling/sampler.h"

#include <limits>
#include <string>

namespace symphong {

/// What light sampling at a point gets from an emitter: a direction, what arrives along it, the
/// density, and the segment a shadow ray must test.
struct EmitterSample {
    Vec3 wi;  ///< unit world direction from the shading point towards the emitter
    /// What arrives along wi: radiance Le for an area or environment emitter; for a delta emitter the
    /// irradiance of a surface facing it (I / d^2 for a point or spot light, E for a directional light).
    Color radiance;
    /// Solid-angle density of wi including the probability `pick` of choosing this emitter; for a delta
    /// emitter (no density) `pick` alone.
    double pdf = 0;
    /// The shadow ray: from the shading point to `target` (stopping just short of it), or along wi to
    /// infinity when `toInfinity`.
    Vec3 target;
    bool toInfinity = false;
    /// The radiance is the emitter's backgroundRadiance(wi), looked up only once the shadow ray is clear
    /// (an environment map: no texture lookup for occluded or back-facing directions); `radiance` unset.
    bool radianceLater = false;
    /// From a delta emitter (a point or a direction): no MIS, since no path can hit it (set by SceneEmitters::sample).
    bool delta = false;
};

class Emitter {
public:
    virtual ~Emitter() = default;

    /// Its kind, as a JSON scene names it ("triangle" for emissive triangles, "environment" for the
    /// environments).
    virtual const char* kind() const = 0;
    /// A point or a direction: only light sampling reaches it, and MIS does not apply.
    virtual bool isDelta() const { return false; }
    /// Seen by rays that leave the scene (environment map, sky, constant environment).
    virtual bool isBackground() const { return false; }
    /// Luminance power for choosing among emitters in proportion to it (sceneRadius: the radius of the
    /// scene's bounding sphere, for emitters at infinity); 0: light sampling never chooses it.
    virtual double power(double sceneRadius) const = 0;
    /// A direction from point p towards the emitter from uniform u in [0,1)^2, chosen with probability
    /// `pick`; false when it brings nothing (zero density, facing away, black, a cut-out).
    virtual bool sample(const Vec3& p, Point2 u, double pick, EmitterSample& s) const = 0;
    /// The density that sample() (with probability `pick`) gives a direction d along which a path from
    /// a point reached it after distance t (t x |d| is the distance; infinity for a background, whose d
    /// is unit length).
    virtual double pdfOfHit(const Vec3& d, double t, double pick) const = 0;
    /// Radiance arriving along unit direction d from a background; 0 for the others.
    virtual Color backgroundRadiance(const Vec3&) const { return Color(0.0); }
    /// backgroundRadiance(d) and pdfOfHit(d, infinity, pick) (as `pdf`) together, for a path that left the
    /// scene along unit d: one lookup where the two share their work (an environment map's mapping of d).
    virtual Color backgroundRadianceAndPdf(const Vec3& d, double pick, double& pdf) const {
        pdf = pdfOfHit(d, std::numeric_limits<double>::infinity(), pick);
        return backgroundRadiance(d);
    }
    /// One line for `symphong info` and the Python Scene: what it is, with its parameters.
    virtual std::string describe() const = 0;
};

}  // namespace symphong
