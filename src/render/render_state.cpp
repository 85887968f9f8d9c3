#include "render/render_state.h"

#include "render/renderer.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace symphong {

double MeanError::relative() const {
    if (!std::isfinite(stdError)) return std::numeric_limits<double>::infinity();
    if (mean == 0) return stdError == 0 ? 0.0 : std::numeric_limits<double>::infinity();
    return stdError / std::abs(mean);
}

RenderState::RenderState(int w, int h, std::uint32_t bound)
    : width(w),
      height(h),
      sppBound(bound),
      sum(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), Color(0.0)),
      sumSq(sum.size(), Color(0.0)),
      sumLuminanceSq(sum.size(), 0.0),
      tileSamples(static_cast<std::size_t>(tileCount(w, h)), 0) {}

std::uint32_t RenderState::samplesReached() const {
    return tileSamples.empty() ? 0 : *std::min_element(tileSamples.begin(), tileSamples.end());
}

namespace {

/// Calls fn(pixel index, samples of its tile) for every pixel.
template <class Fn>
void forEachPixel(const RenderState& s, Fn&& fn) {
    for (int t = 0; t < static_cast<int>(s.tileSamples.size()); ++t)
        forEachTilePixel(t, s.width, s.height, [&](int, int, std::size_t p) { fn(p, s.tileSamples[static_cast<std::size_t>(t)]); });
}

}  // namespace

// The formulas of a one-pass render (render/renderer.cpp), operation for operation.
Image RenderState::image() const {
    Image img(width, height);
    forEachPixel(*this, [&](std::size_t p, std::uint32_t n) {
        if (n > 0) img.pixels[p] = sum[p] / n;
    });
    return img;
}

Image RenderState::variance() const {
    Image img(width, height);
    forEachPixel(*this, [&](std::size_t p, std::uint32_t n) {
        if (n < 2) return;
        const Color mean = sum[p] / n;
        const Color var = vmax(Color(0.0), (sumSq[p] - sum[p] * mean) / (n - 1.0));
        img.pixels[p] = var / n;
    });
    return img;
}

MeanError RenderState::regionError(const PixelRect& r) const {
    const int tilesX = (width + kRenderTile - 1) / kRenderTile;
    double meanSum = 0, varSum = 0;
    std::size_t count = 0;
    for (int y = std::max(0, r.y); y < std::min(height, r.y + r.height); ++y)
        for (int x = std::max(0, r.x); x < std::min(width, r.x + r.width); ++x) {
            const std::uint32_t n = tileSamples[static_cast<std::size_t>((y / kRenderTile) * tilesX + x / kRenderTile)];
            if (n < 2) return {0, std::numeric_limits<double>::infinity()};
            const std::size_t p = static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x);
            const double s = luminance(sum[p]), mean = s / n;
            // Sample variance of Y over the pixel's n samples, then of their mean.
            varSum += std::max(0.0, (sumLuminanceSq[p] - s * mean) / (n - 1.0)) / n;
            meanSum += mean;
            ++count;
        }
    if (count == 0) return {0, std::numeric_limits<double>::infinity()};
    const double c = static_cast<double>(count);
    return {meanSum / c, std::sqrt(varSum) / c};
}

double RenderState::variancePerSample() const {
    double total = 0;
    std::size_t pixels = 0;
    bool known = true;
    forEachPixel(*this, [&](std::size_t p, std::uint32_t n) {
        if (n < 2) return void(known = false);
        const double s = luminance(sum[p]), mean = s / n;
        total += std::max(0.0, (sumLuminanceSq[p] - s * mean) / (n - 1.0));
        ++pixels;
    });
    return known && pixels ? total / static_cast<double>(pixels) : 0.0;
}

}  // namespace symphong
