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

/// A texture from 8-bit texels (width x height x channels bytes, row 0 at the top): each scaled to
/// [0,1], the colour channels (not the alpha of a 2- or 4-channel image) through the sRGB curve under
/// TextureEncoding::Srgb.
Texture textureFrom8Bit(const std::string& name, int width, int height, int channels, const unsigned char* bytes, TextureEncoding encoding);

/// Reads and decodes an image file. Throws MissingFileError when it does not exist, InputError otherwise.
Texture loadTextureFile(const std::string& path, TextureEncoding encoding);

}  // namespace symphong
