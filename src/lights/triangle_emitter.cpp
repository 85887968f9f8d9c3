// An emissive triangle: a uniform point q on it (sampleUniformTriangle), density
//   p(wi) = pick / area x d^2 / cos(theta_L)
// in solid angle at the shading point (d the distance, theta_L the angle at q between the triangle's
// normal and -wi); the emission Ke, or Ke x its texture at q, where a cut-out makes a hole.
#include "lights/kinds.h"
#include "sampling/warp.h"
#include "scene/surface.h"

#include <cmath>

namespace symphong {

namespace {

class TriangleEmitter final : public Emitter {
public:
    TriangleEmitter(const Scene& scene, std::uint32_t prim, double area, const Vec3& normal)
        : scene_(scene),
          triangle_(scene.triangles[prim]),
          material_(scene.materials[triangle_.material]),
          area_(area),
          normal_(normal),
          textured_(material_.textures.any()) {}

    const char* kind() const override { return "triangle"; }
    double power(double) const override { return area_ * luminance(material_.emission); }

    bool sample(const Vec3& p, Point2 u, double pick, EmitterSample& s) const override {
        const Point2 b = sampleUniformTriangle(u);
        const Vec3 q = scene_.positions[triangle_.v[0]] * b.u + scene_.positions[triangle_.v[1]] * b.v +
                       scene_.positions[triangle_.v[2]] * (1.0 - b.u - b.v);
        const Vec3 toLight = q - p;
        const double dist2 = dot(toLight, toLight);
        if (dist2 <= 0) return false;
        s.wi = toLight / std::sqrt(dist2);
        const double cosL = -dot(normal_, s.wi);
        if (cosL <= 0) return false;
        s.pdf = pick / area_ * dist2 / cosL;
        s.target = q;
        s.toInfinity = false;
        s.radiance = material_.emission;
        if (textured_) {
            // q = b.u v0 + b.v v1 + (1 - b.u - b.v) v2: barycentrics (b.v, 1 - b.u - b.v) of vertices 1 and 2.
            const TexCoord uv = texcoordAt(scene_, triangle_, b.v, 1.0 - b.u - b.v);
            if (cutOutAt(scene_, material_, uv)) return false;  // a hole: no path can hit it either
            s.radiance = emissionAt(scene_, material_, uv);
        }
        return true;
    }

    double pdfOfHit(const Vec3& d, double t, double pick) const override {
        const double dist2 = t * t * dot(d, d);
        const double cosL = -dot(normal_, d) / length(d);
        return pick / area_ * dist2 / cosL;
    }

    std::string describe() const override { return "emissive triangle, emission " + formatTriple(material_.emission); }

private:
    const Scene& scene_;
    const Triangle& triangle_;
    const PhongMaterial& material_;
    double area_;
    Vec3 normal_;
    bool textured_;
};

}  // namespace

std::unique_ptr<Emitter> makeTriangleEmitter(const Scene& scene, std::uint32_t prim, double area, const Vec3& normal) {
    return std::make_unique<TriangleEmitter>(scene, prim, area, normal);
}

}  // namespace symphong
