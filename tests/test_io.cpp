// Image output: sRGB encoding, PNG and EXR round trips, and atomic replacement (a write that fails
// half way leaves the target untouched).
#include "io/files.h"
#include "io/image.h"
#include "io/input_error.h"

#include <gtest/gtest.h>
#include <png.h>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>
#include <csignal>
#include <filesystem>

using namespace symphong;
namespace fs = std::filesystem;

namespace {

Image gradient() {
    Image img(5, 3);
    for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 5; ++x) img.at(x, y) = Color(x * 0.25, y * 0.5, 0.125 + x * y);
    return img;
}

fs::path tmp(const std::string& name) { return fs::temp_directory_path() / ("symphong-io-" + name + "-" + std::to_string(::getpid())); }

}  // namespace

TEST(Srgb, EncodesClampsAndAppliesExposure) {
    EXPECT_EQ(toSrgb8(0.0, 1.0), 0);
    EXPECT_EQ(toSrgb8(1.0, 1.0), 255);
    EXPECT_EQ(toSrgb8(7.0, 1.0), 255);
    EXPECT_EQ(toSrgb8(-1.0, 1.0), 0);
    EXPECT_EQ(toSrgb8(std::nan(""), 1.0), 0);
    EXPECT_EQ(toSrgb8(0.2158605, 1.0), 128);  // sRGB 128/255
    EXPECT_EQ(toSrgb8(0.107, 2.0), toSrgb8(0.214, 1.0));
}

TEST(Png, RoundTripsThroughLibpng) {
    const Image img = gradient();
    const auto path = tmp("a.png");
    writePng(img, path.string());
    png_image pi{};
    pi.version = PNG_IMAGE_VERSION;
    ASSERT_TRUE(png_image_begin_read_from_file(&pi, path.string().c_str()));
    pi.format = PNG_FORMAT_RGB;
    std::vector<unsigned char> buf(PNG_IMAGE_SIZE(pi));
    ASSERT_TRUE(png_image_finish_read(&pi, nullptr, buf.data(), 0, nullptr));
    EXPECT_EQ(pi.width, 5u);
    EXPECT_EQ(pi.height, 3u);
    for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 5; ++x)
            for (int c = 0; c < 3; ++c) EXPECT_EQ(buf[(y * 5 + x) * 3 + c], toSrgb8(img.at(x, y)[c], 1.0));
    fs::remove(path);
}

TEST(Exr, FloatRoundTripIsExactAndHalfIsClose) {
    const Image img = gradient();
    const auto f = tmp("f.exr"), h = tmp("h.exr");
    writeExr(img, f.string(), false);
    writeExr(img, h.string(), true);
    const Image rf = readExr(f.string()), rh = readExr(h.string());
    ASSERT_EQ(rf.width, 5);
    ASSERT_EQ(rf.height, 3);
    for (std::size_t i = 0; i < img.pixels.size(); ++i)
        for (int c = 0; c < 3; ++c) {
            EXPECT_FLOAT_EQ(static_cast<float>(rf.pixels[i][c]), static_cast<float>(img.pixels[i][c]));
            EXPECT_NEAR(rh.pixels[i][c], img.pixels[i][c], 1e-3 * (1 + img.pixels[i][c]));
        }
    EXPECT_LT(fs::file_size(h), fs::file_size(f));
    fs::remove(f);
    fs::remove(h);
}

TEST(Exr, ReadingAMissingOrBrokenFileIsAnInputError) {
    EXPECT_THROW(readExr("/nonexistent.exr"), InputError);
    const auto p = tmp("broken.exr");
    {
        std::FILE* f = std::fopen(p.string().c_str(), "wb");
        std::fputs("not an exr", f);
        std::fclose(f);
    }
    EXPECT_THROW(readExr(p.string()), InputError);
    fs::remove(p);
}

TEST(ImageFormat, FromExtension) {
    EXPECT_EQ(imageFormatFor("a/b.PNG"), ImageFormat::Png);
    EXPECT_EQ(imageFormatFor("b.exr"), ImageFormat::Exr);
    EXPECT_THROW(imageFormatFor("b.tiff"), InputError);
    EXPECT_THROW(imageFormatFor("noext"), InputError);
}

// A write that fails half way (here: the file-size limit is hit inside libpng/OpenEXR) leaves the
// target as it was and no temporary file: the writers go through a temporary file and a rename. Run in
// a child process, so the limit does not touch the test runner.
TEST(AtomicWrite, AFailedImageWriteLeavesTheTargetUntouched) {
    for (const char* ext : {".png", ".exr"}) {
        const fs::path dir = tmp(std::string("atomic") + (ext + 1));
        fs::remove_all(dir);
        fs::create_directories(dir);
        const fs::path target = dir / (std::string("image") + ext);
        {
            std::FILE* f = std::fopen(target.string().c_str(), "wb");
            std::fputs("previous contents", f);
            std::fclose(f);
        }
        // A noisy image far larger than the limit once encoded.
        Image big(256, 256);
        std::uint32_t state = 12345;
        for (Color& c : big.pixels) {
            state = state * 1664525u + 1013904223u;
            c = Color((state >> 8) / 16777216.0, (state >> 4 & 0xFFFF) / 65536.0, (state & 0xFFF) / 4096.0);
        }
        const pid_t pid = fork();
        ASSERT_GE(pid, 0);
        if (pid == 0) {
            std::signal(SIGXFSZ, SIG_IGN);  // a write past the limit fails with EFBIG instead of killing us
            rlimit limit{4096, 4096};
            setrlimit(RLIMIT_FSIZE, &limit);
            try {
                writeImage(big, target.string());
            } catch (const InputError&) {
                _exit(3);  // the failure was reported as an input error, as the CLI needs
            } catch (...) {
                _exit(4);
            }
            _exit(0);
        }
        int status = 0;
        waitpid(pid, &status, 0);
        ASSERT_TRUE(WIFEXITED(status)) << ext;
        EXPECT_EQ(WEXITSTATUS(status), 3) << ext << ": the write past the size limit must fail with an InputError";
        EXPECT_EQ(readTextFile(target.string()), "previous contents") << ext << ": a failed write must leave the target untouched";
        std::size_t files = 0;
        for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir)) ++files;
        EXPECT_EQ(files, 1u) << ext << ": the temporary file must be removed";
        fs::remove_all(dir);
    }
}
