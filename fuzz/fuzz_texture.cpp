// fuzz/fuzz_texture.cpp — libFuzzer target for the texture decoder (texture/texture_io.cpp:
// symphong::decodeTexture on bytes in memory: stb_image for PNG, JPEG, BMP, TGA, HDR and the other
// formats stb_image knows, OpenEXR for EXR, the memory check of io/memory.h, the sRGB/linear
// conversion). Bit 0 of the first input byte picks the encoding (0 sRGB, 1 linear); the rest is the
// image file (fuzz_common.h, decodeTextureInput). InputError is the expected rejection; anything else
// escaping, a crash, a sanitizer report or an accepted texture that is not width x height x channels
// finite texels >= 0 is a finding.
#include "fuzz_common.h"

#include <cstddef>
#include <cstdint>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace symphong::fuzz;
    const std::string_view input(reinterpret_cast<const char*>(data), size);
    return runOne([&] { return decodeTextureInput(input); });
}
