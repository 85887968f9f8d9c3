// fuzz/fuzz_json.cpp — libFuzzer target for the JSON scene loader (scene/json_scene.cpp through
// symphong::loadScene on "in.json": nlohmann-json parsing, key checking, lights, material overrides,
// camera, environment, finalizeScene). The input is the JSON text. Beside it lie fixed files the JSON
// may name (fuzz_common.h, loadJsonInput): "floor.obj" (+ "floor.mtl", material "floor"), "lamp.obj"
// (+ "lamp.mtl": an emissive quad, material "lamp"), and through Assimp "tri.gltf" and "tri.ply"; or
// it uses "builtin": "cornell". InputError is the expected rejection; anything else escaping, a crash,
// a sanitizer report or an accepted scene that breaks scene/scene.h's promises is a finding.
#include "fuzz_common.h"

#include <cstddef>
#include <cstdint>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace symphong::fuzz;
    const std::string_view input(reinterpret_cast<const char*>(data), size);
    return runOne([&] { return loadJsonInput(scratchDir("json"), input); });
}
