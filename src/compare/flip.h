// compare/flip.h — the perceptual error FLIP (Andersson et al., "FLIP: A Difference Evaluator for
// Alternating Images", HPG 2020) and HDR-FLIP (Andersson et al., "Visualizing Errors in Rendered High
// Dynamic Range Images", Eurographics 2021), written from the papers: a per-pixel error in [0,1] of
// what a viewer sees when flipping between a test image and its reference, from a colour pipeline
// (contrast sensitivity filters in YCxCz, Hunt-adjusted L*a*b*, HyAB distance, its redistribution) and a
// feature pipeline (edges and points from Gaussian derivatives), combined as colour^(1 - feature).
// HDR-FLIP tone-maps both images at a range of exposures (ACES) and keeps, per pixel, the largest
// LDR-FLIP. Checked against NVIDIA's reference implementation (tests/test_flip.cpp, tests/data/flip/).
#pragma once

#include "io/image.h"

#include <optional>
#include <vector>

namespace symphong {

/// Pixels per degree of visual angle for a viewer `distance` metres from a monitor `monitorWidth`
/// metres wide showing `monitorPixels` pixels across; FLIP's default viewing (0.7 m, 0.7 m, 3840) gives 67.0.
double flipPixelsPerDegree(double distance = 0.7, double monitorWidth = 0.7, double monitorPixels = 3840);

struct FlipResult {
    int width = 0, height = 0;
    std::vector<float> map;  ///< per-pixel error in [0,1], row-major, row 0 at the top
    double mean = 0;         ///< the mean of `map`
    // HDR-FLIP only: the exposures (in stops) at which the images were compared.
    double startExposure = 0, stopExposure = 0;
    int exposures = 0;
};

/// LDR-FLIP of `test` against `reference` (same size; linear RGB, clamped to [0,1] as an sRGB display
/// would show them, e.g. a PNG decoded through the sRGB curve). Throws InputError on a size mismatch.
FlipResult ldrFlip(const Image& reference, const Image& test, double pixelsPerDegree = 67.0);

struct HdrFlipOptions {
    double pixelsPerDegree = 67.0;
    /// The exposure range in stops, when unset computed from the reference's luminance as HDR-FLIP does
    /// (its median and maximum through the ACES tone mapper); the number of exposures, when unset,
    /// ceil(stop - start), at least 2.
    std::optional<double> startExposure, stopExposure;
    std::optional<int> exposures;
};

/// HDR-FLIP of `test` against `reference` (same size; linear RGB radiance, negative values clamped to 0).
/// Throws InputError on a size mismatch.
FlipResult hdrFlip(const Image& reference, const Image& test, const HdrFlipOptions& options = {});

}  // namespace symphong
