// fuzz/fuzz_gltf_ext.cpp — libFuzzer target for the glTF material JSON that symphong reads beside Assimp
// (scene/assimp_materials.cpp and the loader's glTF side-reading: pbrMetallicRoughness, the textureInfos
// with KHR_texture_transform and texCoord, normalTexture's scale, alphaMode, KHR_materials_ior,
// KHR_materials_specular, KHR_materials_emissive_strength). The input is the value of "materials" in a
// fixed glTF (fuzz_common.h, loadGltfExtInput: one textured triangle, two textures of a 2x2 PNG), so that
// Assimp accepts the file and the mutations land in the extensions. InputError is the expected
// rejection; anything else escaping, a crash, a sanitizer report or an accepted scene that breaks
// scene/scene.h's promises (a non-finite texture transform among them) is a finding.
#include "fuzz_common.h"

#include <cstddef>
#include <cstdint>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace symphong::fuzz;
    const std::string_view input(reinterpret_cast<const char*>(data), size);
    return runOne([&] { return loadGltfExtInput(scratchDir("gltf_ext"), input); });
}
