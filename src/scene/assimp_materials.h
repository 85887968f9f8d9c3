// scene/assimp_materials.h — Assimp's materials as Phong materials (private to scene/'s Assimp loader):
// the per-format mapping of docs/scene-format.md (FBX factors, Collada shading models, glTF
// metallic-roughness with its specular, IOR and emissive-strength extensions, files Blender wrote), and
// the texture maps of each material (colour, data, normal and bump maps; glTF's KHR_texture_transform),
// through scene/surface.h's texture table. Also the small JSON helpers the loader reads glTF with.
#pragma once

#include "scene/scene.h"
#include "scene/surface.h"

#include <assimp/material.h>
#include <assimp/scene.h>
#include <nlohmann/json.hpp>

#include <string>

namespace symphong {

inline Vec3 toVec3(const aiVector3D& v) { return {v.x, v.y, v.z}; }
inline Color toColor(const aiColor3D& c) { return {c.r, c.g, c.b}; }

/// The value at a JSON pointer, or null when any step of it is missing or of another type.
nlohmann::json member(const nlohmann::json& j, const std::string& pointer);
/// A finite number at a JSON pointer, or `fallback`.
double number(const nlohmann::json& j, const std::string& pointer, double fallback);

/// Material `index` of the file at `path`: its Phong parameters by the format's conventions (`gltf`: the
/// material's own glTF JSON, null for other formats; `blender`: Blender wrote the file, which changes FBX's numbers), with its
/// textures loaded into `table` and notes added to scene.warnings.
PhongMaterial mapMaterial(const aiScene& ai, const aiMaterial& m, std::size_t index, const nlohmann::json& gltf, bool blender,
                          TextureTable& table, Scene& scene, const std::string& path);

}  // namespace symphong
