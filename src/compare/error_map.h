// compare/error_map.h — errors as pictures: a false-colour map of an image's per-pixel error beside a
// colour bar with its scale written on it, as a PNG. The signed relative error (Y - Y_ref) / (Y_ref + 0.01)
// in a diverging map (blue below the reference, red above, white equal), and FLIP in magma, as the FLIP
// papers show it. Small images are magnified by whole pixels so that the bar's labels stay readable.
#pragma once

#include "compare/flip.h"
#include "io/image.h"

#include <array>
#include <string>
#include <vector>

namespace symphong {

using Rgb8 = std::array<unsigned char, 3>;

/// The diverging map at t in [-1, 1] (matplotlib's RdBu reversed: -1 dark blue, 0 white, +1 dark red).
Rgb8 divergingColour(double t);
/// Magma at t in [0, 1] (matplotlib's, 17 control points, linear between them).
Rgb8 magmaColour(double t);

/// Per-pixel signed relative error of luminance, (Y - Y_ref) / (Y_ref + 0.01).
std::vector<float> signedRelativeError(const Image& test, const Image& reference);

/// A picture of per-pixel values (width x height) through `colour(t)`, t = value scaled to the map's
/// range, with a colour bar labelled at its ends and middle (`labels`: bottom, middle, top).
Image falseColourPicture(const std::vector<float>& values, int width, int height, Rgb8 (*colour)(double), double lo, double hi,
                         const std::array<std::string, 3>& labels);

/// InputError naming `flag` when `path` does not end in .png or cannot be created.
void checkErrorMapPath(const std::string& path, const std::string& flag);

/// The signed relative error of `test` against `reference` from -range to +range, as a PNG.
void writeRelativeErrorMap(const Image& test, const Image& reference, double range, const std::string& path);
/// The FLIP map (0..1, magma), as a PNG.
void writeFlipMap(const FlipResult& flip, const std::string& path);

}  // namespace symphong
