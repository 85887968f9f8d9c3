// io/image.h — a linear RGB image and its writers. PNG is 8-bit sRGB after exposure and clamping;
// OpenEXR is linear float or half RGB. Writers go through a temporary file in the target directory and
// rename it into place, so the target is either the complete new image or untouched.
#pragma once

#include "math/vec3.h"

#include <string>
#include <vector>

namespace symphong {

struct Image {
    int width = 0, height = 0;
    std::vector<Color> pixels;  ///< row-major, row 0 at the top

    Image() = default;
    Image(int w, int h) : width(w), height(h), pixels(static_cast<std::size_t>(w) * h) {}
    Color& at(int x, int y) { return pixels[static_cast<std::size_t>(y) * width + x]; }
    const Color& at(int x, int y) const { return pixels[static_cast<std::size_t>(y) * width + x]; }
};

enum class ImageFormat { Png, Exr };

/// Format from a path's extension (.png / .exr, case-insensitive); throws InputError otherwise.
ImageFormat imageFormatFor(const std::string& path);

/// Creates the directory of `path` if needed and checks that a file can be created there, so that a
/// render fails before it starts, not after. Throws InputError.
void checkWritable(const std::string& path);

/// linear -> 8-bit sRGB: clamp(exposure * v, 0, 1), then the sRGB transfer curve.
unsigned char toSrgb8(double linear, double exposure);

void writePng(const Image& img, const std::string& path, double exposure = 1.0);
void writeExr(const Image& img, const std::string& path, bool half = false);
/// Dispatches on the extension.
void writeImage(const Image& img, const std::string& path, double exposure = 1.0, bool exrHalf = false);

/// Reads a linear RGB OpenEXR image (any of half/float); throws InputError.
Image readExr(const std::string& path);

/// The versions of OpenEXR and libpng this program was built with.
std::string openexrVersion();
std::string libpngVersion();

}  // namespace symphong
