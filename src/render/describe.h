// render/describe.h — what a loaded scene holds, as text: triangles, bounds, camera, materials with their
// Phong parameters and texture maps, the lights and the environment (each described by its emitter,
// lights/), textures and the loader's warnings. `symphong info` prints it and the Python Scene's info()
// returns it, so the two never disagree.
#pragma once

#include "scene/scene.h"

#include <string>

namespace symphong {

/// The description of `scene`, loaded from `spec`, one fact per line (ends with a newline).
std::string describeScene(const Scene& scene, const std::string& spec);

}  // namespace symphong
