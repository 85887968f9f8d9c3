// texture/ — image textures: decoded texels (linear float, 1 to 4 channels), how texture coordinates
// outside [0,1) wrap, and bilinear lookup. texture_io.h decodes image files into them (PNG, JPEG, HDR
// through stb_image; OpenEXR through OpenEXR), turning sRGB-encoded colour maps into linear values.
// Textures know nothing of materials or scenes: scene/ decides what a texture means (an albedo, an
// exponent, a cut-out, an environment) and where on a surface it is looked up.
#pragma once

#include "math/vec3.h"

#include <cstdint>
#include <string>
#include <vector>

namespace symphong {

/// How the stored numbers of an image become linear values.
enum class TextureEncoding {
    Srgb,    ///< colour maps (albedo, emission): 8/16-bit colour channels through the sRGB curve; alpha stays linear
    Linear,  ///< data maps (exponent, metallic-roughness, cut-out) and HDR/EXR images: the numbers as stored
};

/// What a coordinate outside [0,1) reads: the image repeated, its edge texels, or the image mirrored.
enum class WrapMode { Repeat, Clamp, Mirror };

const char* wrapModeName(WrapMode mode);

class Texture {
public:
    Texture() = default;
    /// texels: width x height x channels floats, row-major, row 0 at the top of the image.
    Texture(std::string name, int width, int height, int channels, std::vector<float> texels);

    const std::string& name() const { return name_; }
    int width() const { return width_; }
    int height() const { return height_; }
    int channels() const { return channels_; }
    bool hasAlpha() const { return channels_ == 2 || channels_ == 4; }
    std::uint64_t bytes() const { return texels_.size() * sizeof(float); }

    WrapMode wrapU = WrapMode::Repeat, wrapV = WrapMode::Repeat;

    /// Channel c of texel (x, y), x and y already inside the image.
    float texel(int x, int y, int c) const { return texels_[(static_cast<std::size_t>(y) * width_ + x) * channels_ + c]; }
    /// RGB of texel (x, y): a grey image gives (g, g, g).
    Color texelRgb(int x, int y) const;

    /// Bilinear lookup at texture coordinates (u, v) with u to the right and v up (the OBJ and OpenGL
    /// convention: v = 0 is the bottom row): texel centres at ((i + 0.5) / width, 1 - (j + 0.5) / height),
    /// the four around (u, v) weighted by their distance, coordinates outside [0,1) wrapped.
    Color rgb(double u, double v) const;
    /// Bilinear lookup of one channel (0-based; a channel the image lacks reads 0, and alpha reads 1).
    double channel(double u, double v, int c) const;
    /// Coverage for a cut-out: the alpha channel where the image has one, else its first channel.
    double coverage(double u, double v) const { return channel(u, v, hasAlpha() ? channels_ - 1 : 0); }

    /// Texel (x, y) whose area contains (u, v), no filtering (piecewise constant; environment maps
    /// that are sampled by their texels use it so that what is sampled is exactly what is seen).
    void nearestTexel(double u, double v, int& x, int& y) const;

private:
    template <class Fn>
    void bilinear(double u, double v, Fn&& fn) const;

    std::string name_;
    int width_ = 0, height_ = 0, channels_ = 0;
    std::vector<float> texels_;
};

/// wrapIndex of an i outside [0, n).
int wrapOutside(int i, int n, WrapMode mode);
/// Index of coordinate i in [0, n) under a wrap mode (any integer i). Inside the image every mode leaves i
/// as it is: the divisions of the wrap only at the edges (inline: four calls a bilinear lookup).
inline int wrapIndex(int i, int n, WrapMode mode) { return i >= 0 && i < n ? i : wrapOutside(i, n, mode); }

/// The sRGB transfer curve inverted: an encoded value in [0,1] to linear.
double srgbToLinear(double encoded);

}  // namespace symphong
