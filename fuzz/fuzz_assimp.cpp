// fuzz/fuzz_assimp.cpp — libFuzzer target for the Assimp path (scene/assimp_loader.cpp through
// symphong::loadScene: Assimp's importer with our post-processing flags, the node walk, the material
// table, the glTF JSON side-reading, cameras and lights, finalizeScene). The first input byte picks
// the extension, byte % 6 in order .gltf .glb .ply .fbx .dae .3ds; the rest is the file "in.<ext>"
// (fuzz_common.h, loadAssimpInput). InputError is the expected rejection; anything else escaping, a
// crash, a sanitizer report or an accepted scene that breaks scene/scene.h's promises is a finding.
// Assimp itself (Debian's libassimp5) is not instrumented: libFuzzer has no coverage guidance inside
// it, and a fault inside it shows as a crash of an uninstrumented library (docs/reliability.md).
#include "fuzz_common.h"

#include <cstddef>
#include <cstdint>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace symphong::fuzz;
    const std::string_view input(reinterpret_cast<const char*>(data), size);
    return runOne([&] { return loadAssimpInput(scratchDir("assimp"), input); });
}
