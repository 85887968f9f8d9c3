// compare/: images read whatever wrote them, the metrics of `symphong compare` against closed forms and a
// second computation, regions, error maps, and the command line's output and exit codes.
#include "compare/compare.h"
#include "compare/error_map.h"
#include "compare/image_file.h"
#include "io/image.h"
#include "io/input_error.h"
#include "test_util.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstring>
#include <fstream>
#include <random>

namespace symphong {
namespace {

using test::TempDir;

Image constantImage(int w, int h, const Color& c) {
    Image img(w, h);
    for (Color& p : img.pixels) p = c;
    return img;
}

/// A smooth image with structure: gradients and a bright disc.
Image patternImage(int w, int h) {
    Image img(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const double u = (x + 0.5) / w, v = (y + 0.5) / h;
            const double disc = (u - 0.6) * (u - 0.6) + (v - 0.4) * (v - 0.4) < 0.04 ? 3.0 : 0.0;
            img.at(x, y) = {0.2 + 0.6 * u + disc, 0.1 + 0.5 * v + disc, 0.3 * u * v + 0.05 + disc};
        }
    return img;
}

TEST(Compare, IdenticalImagesHaveNoErrorAndFlipZero) {
    const Image ref = patternImage(40, 30);
    for (const char* kind : {"hdr", "ldr"}) {
        const Comparison c = compareImages(ref, ref, nullptr, {}, kind, 67.0);
        const RegionMetrics& m = c.regions.front();
        EXPECT_EQ(m.mse, 0.0) << kind;
        EXPECT_EQ(m.relMse, 0.0) << kind;
        EXPECT_EQ(m.mseChannel.x + m.mseChannel.y + m.mseChannel.z, 0.0) << kind;
        EXPECT_DOUBLE_EQ(m.meanRatio, 1.0) << kind;
        EXPECT_EQ(m.flipMean, 0.0) << kind;
        for (float f : c.flip.map) ASSERT_EQ(f, 0.0f) << kind;
    }
}

// A constant offset (a, b, c) per channel: MSE per channel is exactly its square, the luminance MSE the
// square of the weighted sum, and relMSE over a constant reference d^2 / (Y_ref^2 + 0.01).
TEST(Compare, ConstantOffsetGivesTheExactErrors) {
    const Color refColour{0.3, 0.5, 0.2}, offset{0.1, -0.05, 0.2};
    const Image ref = constantImage(17, 9, refColour);
    const Image test = constantImage(17, 9, refColour + offset);
    const Comparison c = compareImages(test, ref, nullptr, {}, "off", 67.0);
    const RegionMetrics& m = c.regions.front();
    const double d = 0.2126 * offset.x + 0.7152 * offset.y + 0.0722 * offset.z;
    const double yr = 0.2126 * refColour.x + 0.7152 * refColour.y + 0.0722 * refColour.z;
    EXPECT_NEAR(m.mseChannel.x, 0.01, 1e-15);
    EXPECT_NEAR(m.mseChannel.y, 0.0025, 1e-15);
    EXPECT_NEAR(m.mseChannel.z, 0.04, 1e-15);
    EXPECT_NEAR(m.mse, d * d, 1e-15);
    EXPECT_NEAR(m.rmse, std::abs(d), 1e-12);
    EXPECT_NEAR(m.relMse, d * d / (yr * yr + 0.01), 1e-14);
    EXPECT_NEAR(m.meanRatio, (yr + d) / yr, 1e-12);
    EXPECT_EQ(m.flipMean, -1.0);  // off
}

// The bias's standard error from a variance image: pixels with known variance sigma^2 per channel (equal
// noise in each channel: luminance variance sigma^2) give sigma / sqrt(N); and over independent images
// the z-scores have unit spread (checked within 4 of its own standard errors).
TEST(Compare, BiasStandardErrorFromTheVarianceImage) {
    const int w = 32, h = 32;
    const double sigma = 0.05;
    const Image ref = constantImage(w, h, {0.5, 0.5, 0.5});
    const Image variance = constantImage(w, h, {sigma * sigma, sigma * sigma, sigma * sigma});
    std::mt19937_64 rng(7);
    std::normal_distribution<double> noise(0.0, sigma);
    const int trials = 400;
    double sumZ = 0, sumZ2 = 0;
    for (int t = 0; t < trials; ++t) {
        Image test = ref;
        for (Color& p : test.pixels) {
            const double n = noise(rng);
            p = p + Color{n, n, n};
        }
        const RegionMetrics m = compareImages(test, ref, &variance, {}, "off", 67.0).regions.front();
        ASSERT_TRUE(m.biasStdError.has_value());
        ASSERT_NEAR(*m.biasStdError, sigma / std::sqrt(w * h), 1e-12);
        const double z = (m.meanTest - m.meanReference) / *m.biasStdError;
        sumZ += z, sumZ2 += z * z;
    }
    const double meanZ = sumZ / trials, varZ = sumZ2 / trials - meanZ * meanZ;
    EXPECT_NEAR(meanZ, 0.0, 4.0 / std::sqrt(trials));
    EXPECT_NEAR(varZ, 1.0, 4.0 * std::sqrt(2.0 / trials));  // the sample variance of normals: sd sqrt(2/n)
}

// A rectangle's metrics are those of the same crop compared as a whole image.
TEST(Compare, RectangleRegionEqualsTheCropAsAWhole) {
    const Image ref = patternImage(48, 32);
    Image test = ref;
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> u(-0.2, 0.3);
    for (Color& p : test.pixels) p = p + Color{u(rng), u(rng), u(rng)};
    const auto regions = parseRegions("10,5,20,12", 48, 32);
    ASSERT_EQ(regions.size(), 1u);
    const RegionMetrics r = compareImages(test, ref, nullptr, regions, "off", 67.0).regions.at(1);
    Image cropRef(20, 12), cropTest(20, 12);
    for (int y = 0; y < 12; ++y)
        for (int x = 0; x < 20; ++x) cropRef.at(x, y) = ref.at(10 + x, 5 + y), cropTest.at(x, y) = test.at(10 + x, 5 + y);
    const RegionMetrics whole = compareImages(cropTest, cropRef, nullptr, {}, "off", 67.0).regions.front();
    EXPECT_EQ(r.pixels, 240u);
    EXPECT_NEAR(r.mse, whole.mse, 1e-15);
    EXPECT_NEAR(r.relMse, whole.relMse, 1e-15);
    EXPECT_NEAR(r.meanRatio, whole.meanRatio, 1e-14);
    EXPECT_NEAR(r.mseChannel.y, whole.mseChannel.y, 1e-15);
}

TEST(Compare, MaskRegionsByGreyLevel) {
    TempDir dir;
    Image mask(8, 4);  // left half level 255, two pixels level 128 (sRGB-encoded as written), the rest 0
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x) mask.at(x, y) = {1, 1, 1};
    mask.at(6, 1) = mask.at(7, 3) = Color{0.2158605, 0.2158605, 0.2158605};  // linear for sRGB 128
    writePng(mask, dir.file("mask.png"));
    const auto regions = parseRegions(dir.file("mask.png") + ";0,0,1,1", 8, 4);
    ASSERT_EQ(regions.size(), 3u);
    EXPECT_EQ(regions[0].pixels.size(), 2u);   // level 128 first (levels ascending)
    EXPECT_EQ(regions[1].pixels.size(), 16u);  // level 255
    EXPECT_EQ(regions[2].pixels.size(), 1u);
    EXPECT_THROW(parseRegions(dir.file("mask.png"), 9, 4), InputError);
}

TEST(Compare, BadRegionsAreRefusedByName) {
    for (const char* spec : {"0,0,0,4", "5,5,10,10", "-1,0,2,2", "1,2,3", "abc", "1,2,3,4,5"}) {
        try {
            parseRegions(spec, 8, 8);
            ADD_FAILURE() << spec << " was accepted";
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find(spec), std::string::npos) << e.what();
        }
    }
}

void writePfmFile(const std::string& path, const char* magic, int w, int h, double scale, const std::vector<float>& values,
                  bool littleEndian) {
    std::ofstream out(path, std::ios::binary);
    out << magic << "\n" << w << " " << h << "\n" << scale << "\n";
    for (float v : values) {
        unsigned char b[4];
        std::memcpy(b, &v, 4);  // this machine is little-endian (x86-64)
        if (!littleEndian) std::swap(b[0], b[3]), std::swap(b[1], b[2]);
        out.write(reinterpret_cast<const char*>(b), 4);
    }
}

TEST(ImageFile, PfmBothByteOrdersGreyAndBottomUpRows) {
    TempDir dir;
    // 2 x 2, rows stored bottom first: the file's first row is the image's bottom row.
    const std::vector<float> rgb = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12};
    for (const bool little : {true, false}) {
        const std::string path = dir.file(little ? "le.pfm" : "be.pfm");
        writePfmFile(path, "PF", 2, 2, little ? -1.0 : 1.0, rgb, little);
        const Image img = readImageFile(path).image;
        ASSERT_EQ(img.width, 2);
        EXPECT_EQ(img.at(0, 1).x, 1.0);  // bottom left
        EXPECT_EQ(img.at(1, 1).z, 6.0);
        EXPECT_EQ(img.at(0, 0).y, 8.0);  // top left
    }
    writePfmFile(dir.file("grey.pfm"), "Pf", 2, 1, -1.0, {0.25f, 0.5f}, true);
    const Image grey = readImageFile(dir.file("grey.pfm")).image;
    EXPECT_EQ(grey.at(1, 0).x, 0.5);
    EXPECT_EQ(grey.at(1, 0).z, 0.5);
    writePfmFile(dir.file("short.pfm"), "PF", 4, 4, -1.0, rgb, true);
    EXPECT_THROW(readImageFile(dir.file("short.pfm")), InputError);
}

TEST(ImageFile, PngIsDecodedToLinearAndMarkedLowDynamicRange) {
    TempDir dir;
    Image img(3, 1);
    img.at(0, 0) = {0.0, 0.5, 1.0};
    img.at(1, 0) = {0.214, 0.05, 0.8};
    writePng(img, dir.file("a.png"));
    const ImageFile f = readImageFile(dir.file("a.png"));
    EXPECT_TRUE(f.lowDynamicRange);
    for (int x = 0; x < 2; ++x)
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(f.image.at(x, 0)[c], img.at(x, 0)[c], 0.01) << x << c;  // 8-bit sRGB steps
    writeExr(img, dir.file("a.exr"));
    EXPECT_FALSE(readImageFile(dir.file("a.exr")).lowDynamicRange);
    EXPECT_THROW(readImageFile(dir.file("none.exr")), MissingFileError);
    dir.write("a.txt", "hello");
    EXPECT_THROW(readImageFile(dir.file("a.txt")), InputError);
}

TEST(ErrorMap, ColoursAtTheEndsAndTheMiddle) {
    EXPECT_EQ(magmaColour(0), (Rgb8{0, 0, 4}));
    EXPECT_EQ(magmaColour(1), (Rgb8{252, 253, 191}));
    EXPECT_EQ(divergingColour(0), (Rgb8{247, 246, 246}));
    EXPECT_EQ(divergingColour(-1), (Rgb8{5, 48, 97}));
    EXPECT_EQ(divergingColour(5), (Rgb8{103, 0, 31}));  // clamped
}

// A test image twice as bright as its reference: relative error about +1 everywhere, dark red at
// --error-range 1; the picture is the image magnified to at least 256 rows with the bar beside it.
TEST(ErrorMap, WrittenPictureShowsTheErrorInItsColour) {
    TempDir dir;
    const Image ref = constantImage(32, 16, {0.5, 0.5, 0.5});
    const Image test = constantImage(32, 16, {1.0, 1.0, 1.0});
    writeRelativeErrorMap(test, ref, 1.0, dir.file("err.png"));
    const Image pic = readImageFile(dir.file("err.png")).image;
    EXPECT_EQ(pic.height, 256);
    EXPECT_GT(pic.width, 32 * 16);
    const Rgb8 expected = divergingColour((1.0 - 0.5) / (0.5 + 0.01));
    for (int c = 0; c < 3; ++c) EXPECT_EQ(toSrgb8(pic.at(100, 100)[c], 1.0), expected[c]) << c;
}

TEST(CompareCli, PrintsJsonWritesMapsAndRefusesBadInput) {
    TempDir dir;
    const Image ref = patternImage(24, 16);
    Image test = ref;
    for (Color& p : test.pixels) p = p * 1.1;
    writeExr(ref, dir.file("ref.exr"));
    writeExr(test, dir.file("test.exr"));
    auto run = test::runCliArgs({"compare", dir.file("test.exr"), dir.file("ref.exr"), "--json", "--regions", "0,0,8,8",
                                 "--error-map", dir.file("err.png"), "--flip-map", dir.file("flip.png")});
    ASSERT_EQ(run.code, 0) << run.err;
    const auto j = nlohmann::json::parse(run.out);
    EXPECT_NEAR(j["image"]["mean_ratio"].get<double>(), 1.1, 1e-6);
    EXPECT_EQ(j["flip"]["kind"], "hdr");
    EXPECT_GT(j["image"]["flip"].get<double>(), 0.0);
    EXPECT_TRUE(j["image"]["bias_std_error"].is_null());
    EXPECT_EQ(j["regions"].size(), 1u);
    EXPECT_EQ(j["regions"][0]["pixels"], 64);
    EXPECT_TRUE(std::filesystem::exists(dir.file("err.png")));
    EXPECT_TRUE(std::filesystem::exists(dir.file("flip.png")));

    run = test::runCliArgs({"compare", dir.file("test.exr"), dir.file("ref.exr")});
    ASSERT_EQ(run.code, 0) << run.err;
    EXPECT_NE(run.out.find("FLIP"), std::string::npos) << run.out;
    EXPECT_NE(run.out.find("relMSE"), std::string::npos) << run.out;

    run = test::runCliArgs({"compare", dir.file("missing.exr"), dir.file("ref.exr")});
    EXPECT_EQ(run.code, 2);
    EXPECT_NE(run.err.find("missing.exr"), std::string::npos) << run.err;

    writeExr(patternImage(24, 15), dir.file("small.exr"));
    run = test::runCliArgs({"compare", dir.file("small.exr"), dir.file("ref.exr"), "--error-map", dir.file("never.png")});
    EXPECT_EQ(run.code, 2);
    EXPECT_NE(run.err.find("24 x 15"), std::string::npos) << run.err;
    EXPECT_FALSE(std::filesystem::exists(dir.file("never.png")));

    run = test::runCliArgs({"compare", dir.file("test.exr"), dir.file("ref.exr"), "--error-map", dir.file("err.jpg")});
    EXPECT_EQ(run.code, 2);
    EXPECT_NE(run.err.find("err.jpg"), std::string::npos) << run.err;
    run = test::runCliArgs({"compare", dir.file("test.exr"), dir.file("ref.exr"), "--flip", "sometimes"});
    EXPECT_EQ(run.code, 2);
}

// --variance from `symphong render --variance-output`: the render's own error of the mean against a
// reference rendered with far more samples is small in units of its standard error.
TEST(CompareCli, RenderVarianceGivesTheBiasItsStandardError) {
    TempDir dir;
    auto run = test::runCliArgs({"render", "cornell", "--spp", "8", "--width", "24", "--height", "24", "--seed", "3", "--output",
                                 dir.file("t.exr"), "--variance-output", dir.file("t.var.exr")});
    ASSERT_EQ(run.code, 0) << run.err;
    run = test::runCliArgs({"render", "cornell", "--spp", "512", "--width", "24", "--height", "24", "--seed", "4", "--output",
                            dir.file("r.exr")});
    ASSERT_EQ(run.code, 0) << run.err;
    run = test::runCliArgs({"compare", dir.file("t.exr"), dir.file("r.exr"), "--variance", dir.file("t.var.exr"), "--json"});
    ASSERT_EQ(run.code, 0) << run.err;
    const auto j = nlohmann::json::parse(run.out);
    ASSERT_FALSE(j["image"]["bias_std_error"].is_null());
    EXPECT_GT(j["image"]["bias_std_error"].get<double>(), 0.0);
    EXPECT_LT(std::abs(j["image"]["bias_z"].get<double>()), 4.0);  // unbiased render (the reference's noise is 1/64 of it)
    run = test::runCliArgs({"render", "cornell", "--spp", "1", "--width", "8", "--height", "8", "--output", dir.file("x.png"),
                            "--variance-output", dir.file("x.var.png")});
    EXPECT_EQ(run.code, 2);
    EXPECT_NE(run.err.find("x.var.png"), std::string::npos) << run.err;
}

}  // namespace
}  // namespace symphong
