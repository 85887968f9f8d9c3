// Texture lookups against a second method: the image laid out explicitly as a plane of 7 x 7 tiles (each
// tile the image, mirrored for Mirror, the edge texels stretched for Clamp) and interpolated there with
// plain bilinear weights, no wrapping logic at all; random coordinates far outside [0,1) in both
// directions, negative ones among them. And the sRGB curve against IEC 61966-2-1's formula.
#include "sampling/rng.h"
#include "texture/texture.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

using namespace symphong;

namespace {

constexpr int kW = 5, kH = 3, kTiles = 7;  // tiles -3..3 in each direction

/// Texel (x, y) of the plane of tiles, x in [-3W, 4W), y likewise, built tile by tile from the image.
double planeTexel(const std::vector<float>& img, int x, int y, WrapMode mu, WrapMode mv) {
    const auto axis = [](int i, int n, WrapMode mode) {
        const int tile = static_cast<int>(std::floor(static_cast<double>(i) / n));
        const int within = i - tile * n;
        switch (mode) {
            case WrapMode::Repeat: return within;
            case WrapMode::Mirror: return tile % 2 == 0 ? within : n - 1 - within;  // odd tiles reversed
            case WrapMode::Clamp: return tile < 0 ? 0 : (tile > 0 ? n - 1 : within);
        }
        return within;
    };
    return img[static_cast<std::size_t>(axis(y, kH, mv) * kW + axis(x, kW, mu))];
}

/// Bilinear interpolation on the plane: texel centres at (x + 0.5, y + 0.5) in texel units, y down.
double reference(const std::vector<float>& img, double u, double v, WrapMode mu, WrapMode mv) {
    const double px = u * kW - 0.5, py = (1 - v) * kH - 0.5;
    const int x0 = static_cast<int>(std::floor(px)), y0 = static_cast<int>(std::floor(py));
    const double tx = px - x0, ty = py - y0;
    return planeTexel(img, x0, y0, mu, mv) * (1 - tx) * (1 - ty) + planeTexel(img, x0 + 1, y0, mu, mv) * tx * (1 - ty) +
           planeTexel(img, x0, y0 + 1, mu, mv) * (1 - tx) * ty + planeTexel(img, x0 + 1, y0 + 1, mu, mv) * tx * ty;
}

/// check(texture, image, wrapU, wrapV, u, v) for a random image of kW x kH texels under every pair of wrap
/// modes, at 2000 random (u, v) in (-2.5, 3.5) each: well inside the plane of 7 tiles (-3 .. 4).
template <class Check>
void forEveryWrapMode(std::uint64_t seed, Check&& check) {
    Rng rng(seed, 2);
    std::vector<float> img(kW * kH);
    for (float& t : img) t = static_cast<float>(rng.uniform());
    for (WrapMode mu : {WrapMode::Repeat, WrapMode::Clamp, WrapMode::Mirror})
        for (WrapMode mv : {WrapMode::Repeat, WrapMode::Clamp, WrapMode::Mirror}) {
            Texture tex("t", kW, kH, 1, img);
            tex.wrapU = mu, tex.wrapV = mv;
            for (int i = 0; i < 2000 && !::testing::Test::HasFatalFailure(); ++i) {
                const double u = -2.5 + 6 * rng.uniform(), v = -2.5 + 6 * rng.uniform();
                check(tex, img, mu, mv, u, v);
            }
        }
}

}  // namespace

TEST(TextureLookup, BilinearWithEveryWrapModeMatchesAnExplicitPlaneOfTiles) {
    forEveryWrapMode(41, [](const Texture& tex, const std::vector<float>& img, WrapMode mu, WrapMode mv, double u, double v) {
        ASSERT_NEAR(tex.channel(u, v, 0), reference(img, u, v, mu, mv), 1e-6)
            << wrapModeName(mu) << "/" << wrapModeName(mv) << " at (" << u << ", " << v << ")";
    });
}

// The nearest texel against the same plane: the texel under (u, v) there, for every wrap mode.
TEST(TextureLookup, NearestTexelWithEveryWrapModeIsThePlanesTexel) {
    forEveryWrapMode(43, [](const Texture& tex, const std::vector<float>& img, WrapMode mu, WrapMode mv, double u, double v) {
        int x = -1, y = -1;
        tex.nearestTexel(u, v, x, y);
        const int px = static_cast<int>(std::floor(u * kW)), py = static_cast<int>(std::floor((1 - v) * kH));
        ASSERT_EQ(tex.texelRgb(x, y).x, planeTexel(img, px, py, mu, mv))
            << wrapModeName(mu) << "/" << wrapModeName(mv) << " at (" << u << ", " << v << ")";
    });
}

TEST(TextureLookup, SrgbCurveIsTheStandardsFormula) {
    for (int i = 0; i <= 255; ++i) {
        const double c = i / 255.0;
        const double expected = c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
        EXPECT_NEAR(srgbToLinear(c), expected, 1e-7) << i;
    }
    EXPECT_NEAR(srgbToLinear(0.5), 0.21404114, 1e-7);  // the value every colour tool quotes
}
