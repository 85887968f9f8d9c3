#include "texture/texture.h"

#include <cmath>
#include <utility>

namespace symphong {

const char* wrapModeName(WrapMode mode) {
    switch (mode) {
        case WrapMode::Repeat:
            return "repeat";
        case WrapMode::Clamp:
            return "clamp";
        case WrapMode::Mirror:
            return "mirror";
    }
    return "?";
}

Texture::Texture(std::string name, int width, int height, int channels, std::vector<float> texels)
    : name_(std::move(name)), width_(width), height_(height), channels_(channels), texels_(std::move(texels)) {}

int wrapOutside(int i, int n, WrapMode mode) {
    switch (mode) {
        case WrapMode::Clamp:
            return i < 0 ? 0 : (i >= n ? n - 1 : i);
        case WrapMode::Mirror: {
            // ... 1 0 | 0 1 ... n-1 | n-1 ... : period 2n, the second half reversed.
            int m = i % (2 * n);
            if (m < 0) m += 2 * n;
            return m < n ? m : 2 * n - 1 - m;
        }
        case WrapMode::Repeat:
            break;
    }
    const int m = i % n;
    return m < 0 ? m + n : m;
}

double srgbToLinear(double e) { return e <= 0.04045 ? e / 12.92 : std::pow((e + 0.055) / 1.055, 2.4); }

Color Texture::texelRgb(int x, int y) const {
    if (channels_ < 3) {
        const double g = texel(x, y, 0);
        return Color(g);
    }
    return {texel(x, y, 0), texel(x, y, 1), texel(x, y, 2)};
}

/// Calls fn(x, y, weight) for the four texels around (u, v). Texel (i, j) has its centre at
/// ((i + 0.5) / width, 1 - (j + 0.5) / height); non-finite coordinates read texel (0, 0).
template <class Fn>
void Texture::bilinear(double u, double v, Fn&& fn) const {
    double x = u * width_ - 0.5, y = (1.0 - v) * height_ - 0.5;
    if (!std::isfinite(x) || !std::isfinite(y) || std::abs(x) > 1e9 || std::abs(y) > 1e9) x = y = 0;
    const double fx = std::floor(x), fy = std::floor(y);
    const double tx = x - fx, ty = y - fy;
    const int x0 = static_cast<int>(fx), y0 = static_cast<int>(fy);
    const int xa = wrapIndex(x0, width_, wrapU), xb = wrapIndex(x0 + 1, width_, wrapU);
    const int ya = wrapIndex(y0, height_, wrapV), yb = wrapIndex(y0 + 1, height_, wrapV);
    fn(xa, ya, (1 - tx) * (1 - ty));
    fn(xb, ya, tx * (1 - ty));
    fn(xa, yb, (1 - tx) * ty);
    fn(xb, yb, tx * ty);
}

Color Texture::rgb(double u, double v) const {
    Color c(0.0);
    bilinear(u, v, [&](int x, int y, double w) { c += texelRgb(x, y) * w; });
    return c;
}

double Texture::channel(double u, double v, int c) const {
    if (c >= channels_) return c == 3 ? 1.0 : 0.0;
    double s = 0;
    bilinear(u, v, [&](int x, int y, double w) { s += texel(x, y, c) * w; });
    return s;
}

void Texture::nearestTexel(double u, double v, int& x, int& y) const {
    double fx = std::floor(u * width_), fy = std::floor((1.0 - v) * height_);
    if (!std::isfinite(fx) || !std::isfinite(fy) || std::abs(fx) > 1e9 || std::abs(fy) > 1e9) fx = fy = 0;
    x = wrapIndex(static_cast<int>(fx), width_, wrapU);
    y = wrapIndex(static_cast<int>(fy), height_, wrapV);
}

}  // namespace symphong
