// scene/shading_normal.h — normal and bump maps: how a material's maps bend the shading normal at a point
// of a triangle, in the tangent frame of scene/tangents.h. A tangent-space normal map gives the normal
// directly (its texel c as 2c - 1 along tangent, bitangent and normal); a height map displaces the
// surface along its normal, p' = p + h(u, v) n, whose normal cross(dp'/du, dp'/dv) follows from central
// differences of h half a texel apart (the h dn/du term is left out, as in most renderers). Which MTL
// bump maps are normal maps is decided here too.
#pragma once

#include "scene/scene.h"
#include "scene/surface.h"

namespace symphong {

/// The normal at barycentrics (b1, b2) of triangle tri, texture coordinates uv, bent by the normal and
/// bump maps of `textures`; n is the unbent normal there (the interpolated vertex normal, or the
/// geometric one), and the result lies on n's side. Without a map, or where a map gives nothing usable
/// (a zero texel, degenerate texture coordinates for a height map), n itself.
Vec3 perturbedNormal(const Scene& scene, const Triangle& tri, const MaterialTextures& textures, double b1, double b2, const TexCoord& uv,
                     const Vec3& n);

/// The shadowing term of a bent shading normal (Chiang, Li and Burley, "Taming the Shadow Terminator",
/// SIGGRAPH 2019 talk: its shadowing function and smoothing; what Blender Cycles applies to bump- and normal-mapped
/// diffuse shading): with g = (n_g . w_i) / ((n_s . w_i)(n_s . n_g)),
///   G = 1 for g >= 1,   0 for g < 0,   -g^3 + g^2 + g otherwise,
/// so light that a bent normal n_s faces more than the true surface n_g does is dimmed towards the
/// terminator. n_g, n_s on the same side, w_i towards the light (all unit).
double bumpShadowing(const Vec3& ng, const Vec3& ns, const Vec3& wi);

/// Whether an image looks like a tangent-space normal map rather than a height map: coloured (not
/// grey), and at least 90% of its texels decode (2c - 1) to a vector within 25% of unit length that
/// points out of the surface (z > 0.3). MTL's `bump`/`map_Bump` holds either: Blender writes its normal
/// maps there, older assets their height maps.
bool looksLikeNormalMap(const Texture& texture);

}  // namespace symphong
