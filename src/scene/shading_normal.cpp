#include "scene/shading_normal.h"

#include "math/frame.h"
#include "scene/tangents.h"

#include <algorithm>
#include <cmath>

namespace symphong {

namespace {

const Texture& textureOf(const Scene& scene, const TextureRef& ref) { return scene.textures[static_cast<std::size_t>(ref.index)]; }

/// The unit tangent at the point (interpolated from the triangle's tangents, or its dp/du) made
/// orthogonal to n, and the bitangent's sign.
Vec3 tangentAt(const Scene& scene, const Triangle& tri, double b1, double b2, const Vec3& n, double& sign) {
    Vec3 t(0.0);
    sign = 1;
    if (tri.tg[0] >= 0) {
        const double b[3] = {1.0 - b1 - b2, b1, b2};
        double s = 0;
        for (std::size_t k = 0; k < 3; ++k) {
            const Tangent& tk = scene.tangents[static_cast<std::size_t>(tri.tg[k])];
            t += tk.t * b[k];
            s += tk.sign * b[k];
        }
        sign = s < 0 ? -1 : 1;
    } else {
        Vec3 dpdu, dpdv;
        if (uvDerivatives(scene, tri, dpdu, dpdv)) {
            t = dpdu;
            sign = handedness(scene, tri, dpdu, dpdv);
        }
    }
    t -= n * dot(n, t);
    const double len = length(t);
    return len > 1e-12 && std::isfinite(len) ? t / len : Frame::fromNormal(n).s;
}

/// Tangent-space normal map: n' = normalize(x T + y B + z N), (x, y, z) = (2c - 1) x (s, s, 1).
Vec3 normalMapped(const Scene& scene, const Triangle& tri, const MaterialTextures& tx, double b1, double b2, const TexCoord& uv,
                  const Vec3& n) {
    const TextureRef& ref = tx.normal;
    const Color c = textureOf(scene, ref).rgb(ref.u(uv.u, uv.v), ref.v(uv.u, uv.v));
    const Vec3 local((2 * c.x - 1) * tx.normalScale, (2 * c.y - 1) * tx.normalScale, 2 * c.z - 1);
    double sign;
    const Vec3 t = tangentAt(scene, tri, b1, b2, n, sign);
    const Vec3 b = cross(n, t) * sign;
    const Vec3 out = t * local.x + b * local.y + n * local.z;
    const double len = length(out);
    if (!(len > 1e-12) || !std::isfinite(len)) return n;
    return out / len;
}

/// Height map: p' = p + h n with h = bumpScale x the map's first channel; n' = normalize(cross(dp'/du,
/// dp'/dv)), dp'/du = dp/du + dh/du n (dp/du projected into n's plane), on n's side.
Vec3 bumped(const Scene& scene, const Triangle& tri, const MaterialTextures& tx, const TexCoord& uv, const Vec3& n) {
    Vec3 dpdu, dpdv;
    if (!uvDerivatives(scene, tri, dpdu, dpdv)) return n;
    const TextureRef& ref = tx.bump;
    const Texture& tex = textureOf(scene, ref);
    const auto height = [&](double u, double v) { return tx.bumpScale * tex.channel(ref.u(u, v), ref.v(u, v), 0); };
    // Half a texel of the image, in the mesh's texture coordinates (through the map's transform).
    const auto& m = ref.transform;
    const double w = tex.width(), h = tex.height();
    const double du = 0.5 / std::max({std::abs(m[0]) * w, std::abs(m[3]) * h, 1e-12});
    const double dv = 0.5 / std::max({std::abs(m[1]) * w, std::abs(m[4]) * h, 1e-12});
    const double dhdu = (height(uv.u + du, uv.v) - height(uv.u - du, uv.v)) / (2 * du);
    const double dhdv = (height(uv.u, uv.v + dv) - height(uv.u, uv.v - dv)) / (2 * dv);
    const Vec3 su = dpdu - n * dot(n, dpdu) + n * dhdu;
    const Vec3 sv = dpdv - n * dot(n, dpdv) + n * dhdv;
    Vec3 out = cross(su, sv);
    const double len = length(out);
    if (!(len > 0) || !std::isfinite(len)) return n;
    out /= len;
    return dot(out, n) < 0 ? -out : out;
}

}  // namespace

Vec3 perturbedNormal(const Scene& scene, const Triangle& tri, const MaterialTextures& tx, double b1, double b2, const TexCoord& uv,
                     const Vec3& n) {
    Vec3 out = n;
    if (tx.normal.present()) out = normalMapped(scene, tri, tx, b1, b2, uv, out);
    if (tx.bump.present()) out = bumped(scene, tri, tx, uv, out);
    return out;
}

double bumpShadowing(const Vec3& ng, const Vec3& ns, const Vec3& wi) {
    const double denominator = dot(ns, wi) * dot(ns, ng);
    if (!(denominator > 0)) return 1.0;  // lit from behind the bent normal: the BRDF is 0 there anyway
    const double g = dot(ng, wi) / denominator;
    if (g >= 1) return 1.0;
    if (g < 0) return 0.0;
    const double g2 = g * g;
    return -g2 * g + g2 + g;
}

bool looksLikeNormalMap(const Texture& texture) {
    if (texture.channels() < 3 || texture.width() <= 0 || texture.height() <= 0) return false;
    std::size_t unit = 0, coloured = 0, total = 0;
    // At most about 64 x 64 texels looked at.
    const int stepX = std::max(1, texture.width() / 64), stepY = std::max(1, texture.height() / 64);
    for (int y = 0; y < texture.height(); y += stepY)
        for (int x = 0; x < texture.width(); x += stepX) {
            const Color c = texture.texelRgb(x, y);
            const Vec3 v(2 * c.x - 1, 2 * c.y - 1, 2 * c.z - 1);
            const double len = length(v);
            if (std::abs(len - 1) < 0.25 && v.z > 0.3 * len) ++unit;
            if (std::max({std::abs(c.x - c.y), std::abs(c.y - c.z), std::abs(c.x - c.z)}) > 0.05) ++coloured;
            ++total;
        }
    return unit >= 0.9 * static_cast<double>(total) && coloured >= 0.5 * static_cast<double>(total);
}

}  // namespace symphong
