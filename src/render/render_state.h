// render/render_state.h — what a render has accumulated so far, so that it can proceed in passes, stop
// early and be written to a checkpoint and resumed: per pixel the running sum of its camera samples'
// radiance, of their squares and of their luminance's squares, and per tile the number of samples taken.
// Samples are added to a pixel in the order of their index, whatever the passes, so an image made in any
// number of passes (or resumed from a checkpoint) is bit for bit the image of one pass to the same count.
// The image and its variance are computed from the sums exactly as a one-pass render computes them.
#pragma once

#include "io/image.h"
#include "math/vec3.h"
#include "splitting/learning.h"
#include "util/large_buffer.h"

#include <cstdint>
#include <optional>
#include <vector>

namespace symphong {

struct RenderStats;

/// An axis-aligned rectangle of pixels, [x, x + width) x [y, y + height).
struct PixelRect {
    int x = 0, y = 0, width = 0, height = 0;
};

/// The relative standard error of a region's mean luminance, and that mean.
struct MeanError {
    double mean = 0, stdError = 0;
    double relative() const;
};

struct RenderState {
    int width = 0, height = 0;
    std::uint32_t sppBound = 0;              ///< the render's --spp: its samples' pattern size
    /// Per pixel, row by row (56 bytes a pixel: from 2 MiB on huge pages where the system offers them,
    /// util/large_buffer.h; 15 MB at 512 x 512, whose first touch took 55 ms in small pages here).
    LargeBufferVector<Color> sum, sumSq;
    LargeBufferVector<double> sumLuminanceSq;  ///< per pixel: sum of Y(L)^2 (for the luminance's variance)
    std::vector<std::uint32_t> tileSamples;  ///< per tile (render/renderer.h numbering): samples taken
    std::uint64_t rays = 0, badSamples = 0, samples = 0;
    std::uint64_t paths = 0;  ///< paths started (RenderStats::paths)
    double seconds = 0;       ///< render time so far, over every run that added to this state
    double cpuSeconds = 0;    ///< CPU time so far (RenderStats::cpuSeconds)
    /// --splitting ears: what the render has learned (splitting/learning.h); a checkpoint carries it.
    std::optional<ears::Learning> ears;

    RenderState() = default;
    RenderState(int width, int height, std::uint32_t sppBound);

    /// The fewest samples any tile has; every tile has reached it.
    std::uint32_t samplesReached() const;
    bool finished() const { return samplesReached() >= sppBound; }
    /// --splitting ears rests (ears::Learning::resting): nothing more is looked up, recorded or learned.
    bool earsResting() const { return ears && ears->resting; }

    /// The mean image and the variance of each pixel's mean (zero where a pixel has fewer than 2
    /// samples), each pixel over its own tile's count.
    Image image() const;
    Image variance() const;

    /// The mean luminance of the pixels in `r` and its standard error, from each pixel's sample variance
    /// of luminance (pixels are independent). A pixel with fewer than 2 samples counts as unknown: the
    /// error is then infinite.
    MeanError regionError(const PixelRect& r) const;

    /// The variance of one camera sample's luminance, per pixel, averaged over the image (EARS's V). All
    /// pixels count, fireflies too: the image's MSE, which the factors minimise, has them (leaving out the
    /// largest 0.1% made V of a 2-sample epoch 25x too small on the Cornell box, so the first factors
    /// split far too much). 0 while a pixel has fewer than 2 samples.
    double variancePerSample() const;
};

}  // namespace symphong
