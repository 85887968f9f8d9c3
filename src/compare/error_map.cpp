#include "compare/error_map.h"

#include "io/files.h"
#include "io/input_error.h"
#include "math/vec3.h"
#include "texture/texture.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace symphong {

namespace {

constexpr Rgb8 kMagma[17] = {{0, 0, 4},      {10, 8, 34},     {29, 17, 71},    {54, 16, 107},   {81, 18, 124},   {106, 28, 129},
                             {131, 38, 129}, {156, 46, 127},  {183, 55, 121},  {208, 65, 111},  {231, 82, 99},   {245, 107, 92},
                             {252, 137, 97}, {254, 167, 114}, {254, 196, 136}, {253, 226, 163}, {252, 253, 191}};
constexpr Rgb8 kRdBuReversed[17] = {{5, 48, 97},     {23, 82, 144},   {42, 113, 178},  {63, 142, 192},  {107, 172, 209}, {155, 201, 224},
                                    {194, 221, 236}, {224, 236, 243}, {247, 246, 246}, {251, 229, 216}, {251, 204, 180}, {245, 170, 137},
                                    {228, 128, 102}, {208, 85, 72},   {186, 40, 50},   {147, 14, 38},   {103, 0, 31}};

/// Linear interpolation in a table of 17 colours at t in [0, 1].
Rgb8 fromTable(const Rgb8 (&table)[17], double t) {
    if (!(t > 0)) t = 0;  // also NaN
    t = std::min(t, 1.0) * 16;
    const int i = std::min(static_cast<int>(t), 15);
    const double f = t - i;
    Rgb8 out{};
    for (int c = 0; c < 3; ++c) out[c] = static_cast<unsigned char>(std::lround((1 - f) * table[i][c] + f * table[i + 1][c]));
    return out;
}

/// A 3 x 5 pixel font for the colour bar's labels: each glyph five rows of three bits.
struct Glyph {
    char ch;
    unsigned char rows[5];
};
constexpr Glyph kFont[] = {
    {'0', {7, 5, 5, 5, 7}}, {'1', {2, 6, 2, 2, 7}}, {'2', {7, 1, 7, 4, 7}}, {'3', {7, 1, 7, 1, 7}}, {'4', {5, 5, 7, 1, 1}},
    {'5', {7, 4, 7, 1, 7}}, {'6', {7, 4, 7, 5, 7}}, {'7', {7, 1, 1, 1, 1}}, {'8', {7, 5, 7, 5, 7}}, {'9', {7, 5, 7, 1, 7}},
    {'.', {0, 0, 0, 0, 2}}, {'-', {0, 0, 7, 0, 0}}, {'+', {0, 2, 7, 2, 0}}, {'%', {5, 1, 2, 4, 5}}, {'e', {0, 7, 7, 4, 7}},
};

/// Writes `text` into `img` with its top left at (x, y), each font pixel a `scale` x `scale` square.
void drawText(Image& img, const std::string& text, int x, int y, int scale, const Color& colour) {
    for (char ch : text) {
        for (const Glyph& g : kFont) {
            if (g.ch != ch) continue;
            for (int row = 0; row < 5; ++row)
                for (int col = 0; col < 3; ++col)
                    if (g.rows[row] & (4 >> col))
                        for (int dy = 0; dy < scale; ++dy)
                            for (int dx = 0; dx < scale; ++dx) {
                                const int px = x + col * scale + dx, py = y + row * scale + dy;
                                if (px >= 0 && py >= 0 && px < img.width && py < img.height) img.at(px, py) = colour;
                            }
        }
        x += 4 * scale;
    }
}

/// The linear colour that writePng turns back into these 8-bit sRGB values.
Color linearOf(const Rgb8& c) { return {srgbToLinear(c[0] / 255.0), srgbToLinear(c[1] / 255.0), srgbToLinear(c[2] / 255.0)}; }

}  // namespace

Rgb8 divergingColour(double t) { return fromTable(kRdBuReversed, 0.5 * (t + 1)); }
Rgb8 magmaColour(double t) { return fromTable(kMagma, t); }

std::vector<float> signedRelativeError(const Image& test, const Image& reference) {
    std::vector<float> out(reference.pixels.size());
    for (std::size_t i = 0; i < out.size(); ++i) {
        const double yr = luminance(reference.pixels[i]);
        out[i] = static_cast<float>((luminance(test.pixels[i]) - yr) / (std::abs(yr) + 0.01));
    }
    return out;
}

Image falseColourPicture(const std::vector<float>& values, int width, int height, Rgb8 (*colour)(double), double lo, double hi,
                         const std::array<std::string, 3>& labels) {
    const int scale = std::max(1, (256 + height - 1) / height);  // small images magnified to at least 256 rows
    const int font = 2, margin = 8, barWidth = 16, textWidth = 4 * font * 6;
    const int w = width * scale, h = height * scale;
    Image img(w + 2 * margin + barWidth + textWidth, h);
    const Color background = linearOf({32, 32, 32}), ink = linearOf({230, 230, 230});
    std::fill(img.pixels.begin(), img.pixels.end(), background);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const double v = values[static_cast<std::size_t>(y / scale) * width + x / scale];
            img.at(x, y) = linearOf(colour((v - lo) / (hi - lo) * (lo < 0 ? 2.0 : 1.0) - (lo < 0 ? 1.0 : 0.0)));
        }
    const int barX = w + margin;
    for (int y = 0; y < h; ++y) {
        const double t = 1.0 - (y + 0.5) / h;  // top: the largest value
        const Color c = linearOf(colour(lo < 0 ? 2 * t - 1 : t));
        for (int x = barX; x < barX + barWidth; ++x) img.at(x, y) = c;
    }
    const int textX = barX + barWidth + 4, glyphHeight = 5 * font;
    drawText(img, labels[2], textX, 0, font, ink);
    drawText(img, labels[1], textX, (h - glyphHeight) / 2, font, ink);
    drawText(img, labels[0], textX, h - glyphHeight, font, ink);
    return img;
}

void checkErrorMapPath(const std::string& path, const std::string& flag) {
    if (lowerExtension(path) != ".png") throw InputError(fmt::format("{} {}: the map is a PNG image (name it .png)", flag, path));
    try {
        checkCanCreate(path);
    } catch (const InputError& e) {
        throw InputError(fmt::format("{} {}", flag, e.what()));
    }
}

void writeRelativeErrorMap(const Image& test, const Image& reference, double range, const std::string& path) {
    const std::vector<float> err = signedRelativeError(test, reference);
    const auto pct = [](double v) { return fmt::format("{:+.3g}%", 100 * v); };
    const Image pic = falseColourPicture(err, reference.width, reference.height, divergingColour, -range, range,
                                         {pct(-range), std::string("0"), pct(range)});
    writePng(pic, path);
}

void writeFlipMap(const FlipResult& flip, const std::string& path) {
    const Image pic = falseColourPicture(flip.map, flip.width, flip.height, magmaColour, 0.0, 1.0, {"0", "0.5", "1"});
    writePng(pic, path);
}

}  // namespace symphong
