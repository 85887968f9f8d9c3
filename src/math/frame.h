// math/frame.h — orthonormal frames. A Frame turns world vectors into the local shading space where
// the normal is +Z (the convention of every sampler in sampling/) and back.
#pragma once

#include "math/vec3.h"

namespace symphong {

struct Frame {
    Vec3 s, t, n;  // tangent, bitangent, normal: a right-handed orthonormal basis (s x t = n)

    /// Builds a frame around the unit vector n without branches on its direction
    /// (Duff et al., "Building an Orthonormal Basis, Revisited", JCGT 2017).
    static Frame fromNormal(const Vec3& n) {
        const double sign = std::copysign(1.0, n.z);
        const double a = -1.0 / (sign + n.z);
        const double b = n.x * n.y * a;
        return {Vec3(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x), Vec3(b, sign + n.y * n.y * a, -n.y), n};
    }

    // Always inlined: in the wavefront's long vertex function GCC had made toLocal a call, whose Vec3 came back
    // through memory and cost the vertex a wait on it (docs/performance.md "The estimator's directions ahead").
    [[gnu::always_inline]] Vec3 toLocal(const Vec3& v) const { return {dot(v, s), dot(v, t), dot(v, n)}; }
    [[gnu::always_inline]] Vec3 toWorld(const Vec3& v) const { return s * v.x + t * v.y + n * v.z; }
};

}  // namespace symphong
