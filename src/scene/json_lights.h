// scene/json_lights.h — one light of a JSON scene's "lights" list (docs/scene-format.md#lights): a point,
// spot or directional light, or a quad light (two emissive triangles with a black material of its own,
// named after the element). Shared by the JSON loader and scenes built from arrays in Python
// (python/builder.cpp), so a light means the same thing given either way.
#pragma once

#include "scene/scene.h"

#include <nlohmann/json.hpp>

#include <string>

namespace symphong {

/// Adds light `j` to the scene; `where` names it in messages ("lights[2]"), `path` is the scene's source.
/// Throws InputError naming the element and key for anything missing, unknown or out of range.
void addJsonLight(Scene& scene, const nlohmann::json& j, const std::string& where, const std::string& path);

}  // namespace symphong
