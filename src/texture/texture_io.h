// texture/texture_io.h — decoding image files into textures: PNG, JPEG, BMP, TGA and Radiance HDR through
// stb_image (Debian's libstb), OpenEXR through OpenEXR. Sizes are checked against memory before any
// texel is decoded (io/memory.h); every problem is an InputError naming the file.
#pragma once

#include "texture/texture.h"

#include <cstddef>
#include <string>

namespace symphong {

/// Decodes an image held in memory; `name` names it in messages (its path, or "model.glb: texture 0").
/// 8-bit and 16-bit images are scaled to [0,1] (colour channels through the sRGB curve under
/// TextureEncoding::Srgb); HDR and EXR images keep their linear values, which must be finite and >= 0.
/// Throws InputError on data that is not an image of these formats, is truncated, or would not fit
/// in memory.
Texture decodeTexture(const std::string& name, const unsigned char* data, std::size_t size, TextureEncoding encoding);

/// Reads and decodes an image file. Throws MissingFileError when it does not exist, InputError otherwise.
Texture loadTextureFile(const std::string& path, TextureEncoding encoding);

}  // namespace symphong
