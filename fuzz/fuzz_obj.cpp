// fuzz/fuzz_obj.cpp — libFuzzer target for the Wavefront OBJ + MTL loader (scene/obj_loader.cpp: our
// line-by-line validation, then tinyobjloader, then the conversion to a Scene and finalizeScene) through
// symphong::loadScene on a file "in.obj". The input is the OBJ text, optionally followed by a line
// "#==MTL==" and the text of its material library: that part is written as the file the OBJ's first
// `mtllib` names (when it is a plain file name), else as "in.mtl", so both parsers see fuzzed text
// (fuzz_common.h, loadObjInput). InputError is the expected rejection; anything else escaping, a
// crash, a sanitizer report or an accepted scene that breaks scene/scene.h's promises is a finding.
#include "fuzz_common.h"

#include <cstddef>
#include <cstdint>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace symphong::fuzz;
    const std::string_view input(reinterpret_cast<const char*>(data), size);
    return runOne([&] { return loadObjInput(scratchDir("obj"), input); });
}
