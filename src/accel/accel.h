// accel/ — ray queries. Owns the Intel Embree 3 device and scene built from a Scene's triangles, and
// answers closest-hit and any-hit (shadow) queries for single rays. Geometry crosses into float here;
// everything above it stays in double.
#pragma once

#include "math/vec3.h"
#include "scene/scene.h"

#include <cstdint>

struct RTCDeviceTy;
struct RTCSceneTy;

namespace symphong {

struct Hit {
    double t = 0;
    std::uint32_t prim = 0;  ///< triangle index in Scene::triangles
    double u = 0, v = 0;     ///< barycentrics of vertices 1 and 2
};

class Accel {
public:
    explicit Accel(const Scene& scene);
    ~Accel();
    Accel(const Accel&) = delete;
    Accel& operator=(const Accel&) = delete;

    /// Closest hit along o + t d, t in (tnear, tfar). d need not be unit length.
    bool intersect(const Vec3& o, const Vec3& d, double tnear, double tfar, Hit& hit) const;
    /// Whether anything blocks o + t d for t in (tnear, tfar).
    bool occluded(const Vec3& o, const Vec3& d, double tnear, double tfar) const;

    RTCSceneTy* handle() const { return scene_; }

private:
    RTCDeviceTy* device_ = nullptr;
    RTCSceneTy* scene_ = nullptr;
};

}  // namespace symphong
