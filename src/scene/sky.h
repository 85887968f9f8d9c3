// scene/sky.h — the default sky: what lights a scene that brings no light of its own (no emissive
// material, no light, no "environment"), so that a white model reads as a shaded object instead of
// white on white. A soft gradient (white at the horizon, blue at the zenith, a darker ground below)
// seen by rays that leave the scene, with a sun (a directional light, added to Scene::lights).
#pragma once

#include "math/vec3.h"
#include "scene/light.h"

namespace symphong {

struct Sky {
    Color zenith{0.25, 0.42, 0.80};
    Color horizon{0.85, 0.87, 0.9};
    Color ground{0.30, 0.28, 0.26};
    Vec3 up{0, 1, 0};  ///< unit length
};

/// Radiance of the sky seen along unit direction d: with t = d . up, horizon -> zenith as sqrt(t) above
/// the horizon; horizon -> ground within 15 degrees below it (|t| < 0.25), ground further down.
inline Color skyRadiance(const Sky& sky, const Vec3& d) {
    const double t = dot(d, sky.up);
    if (t >= 0) return sky.horizon + (sky.zenith - sky.horizon) * std::sqrt(std::min(t, 1.0));
    return sky.horizon + (sky.ground - sky.horizon) * std::min(1.0, -t * 4.0);
}

/// The default sky's sun: from high over the viewer's left shoulder (for the automatic camera, which
/// looks from +X+Z), irradiance 1.6 on a surface facing it.
inline Light defaultSun() {
    Light sun;
    sun.type = Light::Type::Directional;
    sun.direction = normalize(Vec3(-0.2, -1.0, -0.55));
    sun.intensity = Color(1.6, 1.55, 1.45);
    return sun;
}

}  // namespace symphong
