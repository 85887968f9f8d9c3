// fuzz/fuzz_ply.cpp — libFuzzer target for symphong's own PLY reader (scene/ply_loader.cpp through
// symphong::loadScene on "in.ply": the header's elements and properties, ASCII and binary of either byte
// order, list counts, faces fanned into triangles, triangle strips with their restarts, normals and
// texture coordinates, the memory check, finalizeScene). The input is the file. InputError is the
// expected rejection; anything else escaping, a crash, a sanitizer report or an accepted scene that
// breaks scene/scene.h's promises is a finding.
#include "fuzz_common.h"

#include <cstddef>
#include <cstdint>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace symphong::fuzz;
    const std::string_view input(reinterpret_cast<const char*>(data), size);
    return runOne([&] { return loadPlyInput(scratchDir("ply"), input); });
}
