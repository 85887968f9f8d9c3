// compare/compare.h — `symphong compare` and symphong.compare(): a test image against a reference, as a
// whole and region by region. Luminance and per-channel MSE / RMSE, relMSE, the means and their ratio,
// the bias of the mean with its standard error when the test image comes with its variance image, and
// the perceptual error FLIP (HDR-FLIP for linear images, LDR-FLIP when both are 8-bit display images).
// Its options are one schema (util/schema.h), so the command line, Python and JSON share them.
#pragma once

#include "compare/flip.h"
#include "io/image.h"
#include "util/schema.h"

#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <vector>

namespace symphong {

struct CompareOptions {
    std::string test, reference;            ///< image files
    std::string variance;                   ///< the test image's per-pixel variance of the mean (EXR/PFM), optional
    std::string regions;                    ///< ";"-separated: "X,Y,W,H" rectangles or mask images (each grey level > 0 a region)
    std::string errorMap;                   ///< PNG: signed relative error in false colour with a colour bar
    std::string flipMap;                    ///< PNG: the FLIP map (magma) with a colour bar
    double errorRange = 1.0;                ///< the error map's colour scale: +-range (1 = +-100%)
    double pixelsPerDegree = 67.0;          ///< FLIP's viewing condition
    std::string flip = "auto";              ///< auto (LDR for two 8-bit images, else HDR), hdr, ldr, off
    bool json = false;                      ///< print JSON instead of the table
};

/// Every field of CompareOptions, in the order `symphong compare --help` lists them.
const schema::Schema<CompareOptions>& compareSchema();

/// A set of pixels measured on its own: a rectangle, a mask's grey level, or the whole image.
struct Region {
    std::string name;
    std::vector<std::size_t> pixels;  ///< indices into the image, row-major
};

/// The regions of --regions for an image of this size: InputError naming the text or the mask file when
/// a rectangle leaves the image, is empty, or a mask's size differs.
std::vector<Region> parseRegions(const std::string& specs, int width, int height);

struct RegionMetrics {
    std::string name;
    std::size_t pixels = 0;
    double mse = 0, rmse = 0, relMse = 0;              ///< luminance
    Color mseChannel, rmseChannel;                     ///< per channel
    double meanTest = 0, meanReference = 0;            ///< mean luminance
    double meanRatio = 0;                              ///< meanTest / meanReference (0 when the reference is black)
    std::optional<double> biasStdError;                ///< of meanTest - meanReference, from the variance image
    double flipMean = -1;                              ///< -1: FLIP was not computed
};

struct Comparison {
    int width = 0, height = 0;
    std::string flipKind;  ///< "hdr", "ldr" or "off"
    FlipResult flip;       ///< map empty when off
    std::vector<RegionMetrics> regions;  ///< the whole image first, then --regions in order
};

/// Measures `test` against `reference` (same size; InputError otherwise) over the whole image and each region.
/// `variance`: the test image's variance of the mean per pixel and channel (same size) or null.
Comparison compareImages(const Image& test, const Image& reference, const Image* variance, const std::vector<Region>& regions,
                         const std::string& flipKind, double pixelsPerDegree);

/// compareImages with --regions, --flip (auto: LDR-FLIP when both images were 8-bit files) and the maps
/// written; sizes are checked first (InputError naming o.test, o.reference, o.variance), then the
/// output paths, before any work.
Comparison compareLoaded(const Image& test, const Image& reference, const Image* variance, bool bothLowDynamicRange,
                         const CompareOptions& o);

/// The whole of `symphong compare`: reads the files, compares, writes the maps. InputError for bad input.
Comparison runComparison(const CompareOptions& o);

nlohmann::json comparisonJson(const Comparison& c, const CompareOptions& o);
/// The table `symphong compare` prints.
std::string comparisonText(const Comparison& c, const CompareOptions& o);

}  // namespace symphong
