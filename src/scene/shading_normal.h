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

/// Whether an image looks like a tangent-space normal map rather than a height map: coloured (not
/// grey), and at least 90% of its texels decode (2c - 1) to a vector within 25% of unit length that
/// points out of the surface (z > 0.3). MTL's `bump`/`map_Bump` holds either: Blender writes its normal
/// maps there, older assets their height maps.
bool looksLikeNormalMap(const Texture& texture);

}  // namespace symphong
