// scene/light.h — lights that are not emissive triangles: point, spot and directional lights, as a JSON
// scene's "lights" list gives them (docs/scene-format.md). They are points or directions, so no path can
// hit them: only light sampling reaches them (render/path_tracer). A JSON "quad" light is not one of
// these: it becomes two emissive triangles, found by paths and light sampling alike.
#pragma once

#include "math/vec3.h"

#include <string>

namespace symphong {

struct Light {
    enum class Type { Point, Spot, Directional };
    Type type = Type::Point;
    Vec3 position{0, 0, 0};    ///< point, spot
    Vec3 direction{0, -1, 0};  ///< spot: its axis; directional: the direction the light travels (unit length)
    /// Point, spot: radiant intensity I, so a surface at distance d facing it receives E = I / d^2.
    /// Directional: the irradiance E of a surface facing it.
    Color intensity{1.0};
    /// Spot: cosines of the half-angles of full intensity (inner) and of no light (outer); between
    /// them the intensity falls off smoothly (smoothstep in the cosine, as pbrt-v4's spot light).
    double cosInner = 1.0, cosOuter = 0.0;
};

const char* lightTypeName(Light::Type type);

/// Spot light falloff for a direction at cosine `cosTheta` from the axis: 1 inside the inner cone, 0
/// outside the outer one, smoothstep between.
inline double spotFalloff(double cosTheta, double cosInner, double cosOuter) {
    if (cosTheta >= cosInner) return 1.0;
    if (cosTheta <= cosOuter) return 0.0;
    const double t = (cosTheta - cosOuter) / (cosInner - cosOuter);
    return t * t * (3.0 - 2.0 * t);
}

}  // namespace symphong
