// An emissive triangle: a uniform point q on it (sampleUniformTriangle), density
//   p(wi) = pick / area x d^2 / cos(theta_L)
// in solid angle at the shading point (d the distance, theta_L the angle at q between the triangle's
// normal and -wi); the emission Ke, or Ke x its texture at q, where a cut-out makes a hole. The
// triangle is a row of SceneEmitters' table (lights/kinds.h TriangleLight), sampled without a virtual call.
#include "lights/kinds.h"
#include "sampling/warp.h"
#include "scene/surface.h"

#include <cmath>

namespace symphong {

TriangleLight makeTriangleLight(const Scene& scene, std::uint32_t prim, double area, const Vec3& normal) {
    const Triangle& tri = scene.triangles[prim];
    const PhongMaterial& m = scene.materials[tri.material];
    TriangleLight t;
    t.v0 = scene.positions[tri.v[0]], t.v1 = scene.positions[tri.v[1]], t.v2 = scene.positions[tri.v[2]];
    t.normal = normal;
    t.area = area;
    t.pick = 1;
    t.pickOverArea = 1.0 / area;
    t.emission = m.emission;
    t.prim = prim;
    t.textured = m.textures.any();
    return t;
}

bool sampleTriangleLight(const TriangleLight& t, const Scene& scene, const Vec3& p, Point2 u, EmitterSample& s) {
    const Point2 b = sampleUniformTriangle(u);
    const Vec3 q = t.v0 * b.u + t.v1 * b.v + t.v2 * (1.0 - b.u - b.v);
    const Vec3 toLight = q - p;
    const double dist2 = dot(toLight, toLight);
    if (dist2 <= 0) return false;
    s.wi = toLight / std::sqrt(dist2);
    const double cosL = -dot(t.normal, s.wi);
    if (cosL <= 0) return false;
    s.pdf = t.pickOverArea * dist2 / cosL;
    s.target = q;
    s.toInfinity = false;
    s.delta = false;
    s.radianceLater = false;
    s.radiance = t.emission;
    if (t.textured) {
        // q = b.u v0 + b.v v1 + (1 - b.u - b.v) v2: barycentrics (b.v, 1 - b.u - b.v) of vertices 1 and 2.
        const Triangle& tri = scene.triangles[t.prim];
        const PhongMaterial& m = scene.materials[tri.material];
        const TexCoord uv = texcoordAt(scene, tri, b.v, 1.0 - b.u - b.v);
        if (cutOutAt(scene, m, uv)) return false;  // a hole: no path can hit it either
        s.radiance = emissionAt(scene, m, uv);
    }
    return true;
}

}  // namespace symphong
