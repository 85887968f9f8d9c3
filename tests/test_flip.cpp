// FLIP and HDR-FLIP (compare/flip.h) against NVIDIA's reference tool: the pairs in tests/data/flip and the
// tool's means, exposure range and error maps for them (tests/data/flip/README.md says how they were made).
#include "compare/flip.h"
#include "io/image.h"
#include "io/input_error.h"

#include <gtest/gtest.h>
#include <png.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

using namespace symphong;

namespace {

const std::string kData = SYMPHONG_SOURCE_DIR "/tests/data/flip/";

// What the reference tool printed for the pairs (README.md): means to 6 decimals, exposures to 4.
constexpr double kToolLdrMean = 0.101233;
constexpr double kToolHdrMean = 0.213647;
constexpr double kToolHdrStart = -2.5792, kToolHdrStop = 5.4880;
constexpr int kToolHdrExposures = 9;

// Tolerance on the means: the tool's rounding to 6 decimals (5e-7) plus 1e-5 of the mean. The tool works in
// float32; we filter in float32 too (columns before rows, the tool rows before columns) but do the
// per-pixel colour arithmetic, the filter weights and the mean in double. On these pairs our means differ
// from the tool library's unrounded float32 means by 3e-8 relative at most (its float maps from ours by
// 1e-5 at most), so 1e-5 is a margin of ~300x on the arithmetic; it is tighter than the ~1e-4 one might
// expect from float32 vs double, because at 1e-4 a 4% change of the smallest CSF constant (b2 of Cz)
// still passed.
double meanTolerance(double toolMean) { return 5e-7 + 1e-5 * toolMean; }

std::vector<std::uint8_t> readPngRgb8(const std::string& path, int& width, int& height) {
    png_image img{};
    img.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_file(&img, path.c_str())) throw std::runtime_error(path + ": " + img.message);
    img.format = PNG_FORMAT_RGB;
    std::vector<std::uint8_t> bytes(PNG_IMAGE_SIZE(img));
    if (!png_image_finish_read(&img, nullptr, bytes.data(), 0, nullptr)) throw std::runtime_error(path + ": " + img.message);
    width = static_cast<int>(img.width);
    height = static_cast<int>(img.height);
    return bytes;
}

// An 8-bit sRGB PNG as linear RGB, decoded as the tool decodes it: v / 255 through the sRGB curve.
Image readSrgbPng(const std::string& path) {
    int w = 0, h = 0;
    const auto bytes = readPngRgb8(path, w, h);
    Image img(w, h);
    const auto linear = [](std::uint8_t b) {
        const double v = b / 255.0;
        return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
    };
    for (std::size_t i = 0; i < img.pixels.size(); ++i)
        img.pixels[i] = Color(linear(bytes[3 * i]), linear(bytes[3 * i + 1]), linear(bytes[3 * i + 2]));
    return img;
}

// The tool's grey error map (--no-magma): round(255 v) in each channel.
std::vector<double> readToolMap(const std::string& path, int& width, int& height) {
    const auto bytes = readPngRgb8(path, width, height);
    std::vector<double> map(static_cast<std::size_t>(width) * height);
    for (std::size_t i = 0; i < map.size(); ++i) map[i] = bytes[3 * i] / 255.0;
    return map;
}

// Our map against the tool's 8-bit one: within 2/255 on at least 99.9% of the pixels, and, as the maps
// agree to ~1e-5 before the tool rounds its map to 8 bits (0.5/255), within 1/255 everywhere.
void expectMapAgrees(const FlipResult& ours, const std::string& toolPng) {
    int w = 0, h = 0;
    const std::vector<double> tool = readToolMap(toolPng, w, h);
    ASSERT_EQ(w, ours.width);
    ASSERT_EQ(h, ours.height);
    ASSERT_EQ(ours.map.size(), tool.size());
    std::size_t within = 0;
    double worst = 0;
    for (std::size_t i = 0; i < tool.size(); ++i) {
        const double d = std::abs(ours.map[i] - tool[i]);
        within += d <= 2.0 / 255.0;
        worst = std::max(worst, d);
    }
    EXPECT_GE(static_cast<double>(within) / tool.size(), 0.999) << "largest difference " << worst * 255 << "/255";
    EXPECT_LE(worst, 1.0 / 255.0);
}

void expectAllZero(const FlipResult& r) {
    EXPECT_EQ(r.mean, 0.0);
    for (float v : r.map) ASSERT_EQ(v, 0.0f);
}

// Adds noise of amplitude `amplitude` (uniform, in display units) from a fixed LCG, clamped to [0,1].
Image withNoise(const Image& img, double amplitude) {
    Image out = img;
    std::uint64_t state = 12345;
    const auto uniform = [&] {
        state = state * 6364136223846793005ULL + 1442695040888963407ULL;
        return static_cast<double>(state >> 11) / 9007199254740992.0;  // [0,1)
    };
    for (Color& c : out.pixels)
        for (int k = 0; k < 3; ++k) c[k] = std::clamp(c[k] + amplitude * (2.0 * uniform() - 1.0), 0.0, 1.0);
    return out;
}

}  // namespace

TEST(FlipPixelsPerDegree, DefaultViewingIsThePaperClosedForm) {
    // 0.7 m * (3840 px / 0.7 m) * (pi / 180) = 3840 pi / 180 = 67.0206..., which FLIP calls "67 ppd".
    EXPECT_NEAR(flipPixelsPerDegree(), 3840.0 * kPi / 180.0, 1e-12);
    EXPECT_NEAR(flipPixelsPerDegree(), 67.02, 0.01);
    EXPECT_NEAR(flipPixelsPerDegree(0.5, 0.6, 1920), 0.5 * 3200 * kPi / 180.0, 1e-12);
}

TEST(Flip, IdenticalImagesGiveZero) {
    const Image ref = readSrgbPng(kData + "ldr_reference.png");
    const FlipResult r = ldrFlip(ref, ref);
    EXPECT_EQ(r.width, ref.width);
    EXPECT_EQ(r.height, ref.height);
    ASSERT_EQ(r.map.size(), ref.pixels.size());
    expectAllZero(r);
}

TEST(HdrFlip, IdenticalImagesGiveZero) {
    const Image ref = readExr(kData + "hdr_reference.exr");
    const FlipResult r = hdrFlip(ref, ref);
    ASSERT_EQ(r.map.size(), ref.pixels.size());
    expectAllZero(r);
    EXPECT_EQ(r.exposures, kToolHdrExposures);  // from the reference alone
}

TEST(Flip, AgreesWithNvidiaReferenceTool) {
    const FlipResult r = ldrFlip(readSrgbPng(kData + "ldr_reference.png"), readSrgbPng(kData + "ldr_test.png"));
    EXPECT_NEAR(r.mean, kToolLdrMean, meanTolerance(kToolLdrMean));
    expectMapAgrees(r, kData + "ldr_flip_tool.png");
}

TEST(HdrFlip, AgreesWithNvidiaReferenceTool) {
    const FlipResult r = hdrFlip(readExr(kData + "hdr_reference.exr"), readExr(kData + "hdr_test.exr"));
    EXPECT_NEAR(r.startExposure, kToolHdrStart, 1e-4);  // printed to 4 decimals
    EXPECT_NEAR(r.stopExposure, kToolHdrStop, 1e-4);
    EXPECT_EQ(r.exposures, kToolHdrExposures);
    EXPECT_NEAR(r.mean, kToolHdrMean, meanTolerance(kToolHdrMean));
    expectMapAgrees(r, kData + "hdr_flip_tool.png");
}

TEST(HdrFlip, UsesTheExposuresItIsGiven) {
    const Image ref = readExr(kData + "hdr_reference.exr"), test = readExr(kData + "hdr_test.exr");
    HdrFlipOptions o;
    o.startExposure = -1.0;
    o.stopExposure = 2.5;
    const FlipResult r = hdrFlip(ref, test, o);
    EXPECT_EQ(r.startExposure, -1.0);
    EXPECT_EQ(r.stopExposure, 2.5);
    EXPECT_EQ(r.exposures, 4);  // ceil(3.5)
    o.exposures = 1;
    o.stopExposure = -1.0;
    const FlipResult one = hdrFlip(ref, test, o);
    EXPECT_EQ(one.exposures, 1);
    EXPECT_GT(one.mean, 0.0);
    EXPECT_LE(one.mean, r.mean);  // the maximum over more exposures, the one at -1 among them
    o.stopExposure = -2.0;
    EXPECT_THROW(hdrFlip(ref, test, o), InputError);  // start > stop
}

TEST(Flip, MoreNoiseGivesMoreError) {
    const Image ref = readSrgbPng(kData + "ldr_reference.png");
    const double weak = ldrFlip(ref, withNoise(ref, 0.02)).mean, strong = ldrFlip(ref, withNoise(ref, 0.08)).mean;
    EXPECT_GT(weak, 0.0);
    EXPECT_GT(strong, weak * 1.5);
    const Image hdr = readExr(kData + "hdr_reference.exr");
    Image hdrWeak = hdr, hdrStrong = hdr;
    for (std::size_t i = 0; i < hdr.pixels.size(); ++i) {
        const double s = (i * 7919 % 13) / 6.0 - 1.0;  // fixed pattern in [-1, 1]
        hdrWeak.pixels[i] = hdr.pixels[i] * (1.0 + 0.05 * s);
        hdrStrong.pixels[i] = hdr.pixels[i] * (1.0 + 0.3 * s);
    }
    EXPECT_GT(hdrFlip(hdr, hdrStrong).mean, hdrFlip(hdr, hdrWeak).mean);
}

TEST(Flip, SizeMismatchThrowsInputError) {
    const Image a(8, 8), b(8, 9), c(9, 8);
    EXPECT_THROW(ldrFlip(a, b), InputError);
    EXPECT_THROW(ldrFlip(a, c), InputError);
    EXPECT_THROW(hdrFlip(a, b), InputError);
    EXPECT_THROW(hdrFlip(c, a), InputError);
    EXPECT_NO_THROW(ldrFlip(a, a));
}

TEST(Flip, TinyAndEmptyImages) {
    Image a(1, 1), b(1, 1);
    b.at(0, 0) = Color(1, 0, 0);
    const FlipResult r = ldrFlip(a, b);
    ASSERT_EQ(r.map.size(), 1u);
    EXPECT_GT(r.map[0], 0.0f);
    EXPECT_LE(r.map[0], 1.0f);
    EXPECT_EQ(ldrFlip(Image(), Image()).mean, 0.0);
    const FlipResult black = hdrFlip(Image(4, 4), Image(4, 4));  // an all-black reference: exposures 0 to 0
    EXPECT_EQ(black.startExposure, 0.0);
    EXPECT_EQ(black.stopExposure, 0.0);
    expectAllZero(black);
}
