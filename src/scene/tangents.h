// scene/tangents.h — tangent frames for normal and bump maps. A triangle's derivatives dp/du and dp/dv
// follow from its positions and texture coordinates; a vertex's tangent is the average of its triangles'
// dp/du, each projected into the plane of the vertex normal and weighted by the triangle's angle at the
// vertex, in the manner of MikkTSpace (Mikkelsen 2008, the convention Blender, Substance and glTF bake
// normal maps in): vertices are shared only by triangles that share position, normal and texture
// coordinate, and that agree on the handedness of (dp/du, dp/dv), so a mirrored half of a texture keeps
// its own tangents. Files that carry tangents (glTF's TANGENT) keep theirs.
#pragma once

#include "scene/scene.h"

namespace symphong {

/// dp/du and dp/dv of triangle tri from its positions and texture coordinates (with none, its
/// barycentrics: dp/du = p1 - p0, dp/dv = p2 - p0). False where its texture coordinates are degenerate
/// (the triangle's uv area is zero), leaving dpdu and dpdv untouched.
bool uvDerivatives(const Scene& scene, const Triangle& tri, Vec3& dpdu, Vec3& dpdv);

/// The normal of triangle tri at its corner k: its vertex normal, or the geometric one (counter-clockwise).
Vec3 cornerNormal(const Scene& scene, const Triangle& tri, int k);

/// The handedness of (dp/du, dp/dv) about the triangle's normals (the sum of its corner normals, so a
/// file whose winding disagrees with its vertex normals is read by its normals): +1 where
/// cross(n, dp/du) runs along dp/dv, else -1 (a mirrored texture).
int handedness(const Scene& scene, const Triangle& tri, const Vec3& dpdu, const Vec3& dpdv);

/// Fills Scene::tangents and Triangle::tg for every triangle whose material has a normal or bump map
/// and whose tangents the file did not give. Returns how many triangles got computed tangents.
std::size_t computeTangents(Scene& scene);

}  // namespace symphong
