// Every render option reaches the image it promises to change, read back from the written file:
// dimensions, --exposure (PNG only), --exr-half (the pixel type in the EXR header), the default output
// path, --max-depth, --no-nee, --paper-refined, --symmetric-n, --seed; the progress bar on a terminal
// (a pseudo-terminal) and not elsewhere; every scene in scenes/ renders.
#include "cli/cli.h"
#include "io/files.h"
#include "io/image.h"
#include "test_util.h"

#include <ImfChannelList.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <gtest/gtest.h>
#include <png.h>
#include <pty.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>

using namespace symphong;
namespace fs = std::filesystem;

namespace {

using test::CliRun;

CliRun run(std::vector<std::string> args) { return test::runCliArgs(std::move(args)); }

struct Png {
    unsigned width = 0, height = 0;
    std::vector<unsigned char> rgb;
};

Png readPng(const std::string& path) {
    png_image pi{};
    pi.version = PNG_IMAGE_VERSION;
    Png out;
    if (!png_image_begin_read_from_file(&pi, path.c_str())) return out;
    pi.format = PNG_FORMAT_RGB;
    out.rgb.resize(PNG_IMAGE_SIZE(pi));
    if (!png_image_finish_read(&pi, nullptr, out.rgb.data(), 0, nullptr)) return out;
    out.width = pi.width;
    out.height = pi.height;
    return out;
}

double meanOf(const Image& img) {
    double s = 0;
    for (const Color& c : img.pixels) s += luminance(c);
    return s / static_cast<double>(img.pixels.size());
}

class CliOptions : public ::testing::Test {
protected:
    std::string out(const std::string& name) const { return tmp_.file(name); }
    /// Renders the built-in Cornell box with `extra` options into `file`; fails the test on error.
    void render(const std::string& file, std::vector<std::string> extra) {
        std::vector<std::string> args = {"render", "--seed", "5", "-W", "24", "-H", "20", "-s", "4", "-o", out(file)};
        args.insert(args.end(), extra.begin(), extra.end());
        const CliRun r = run(args);
        ASSERT_EQ(r.code, 0) << r.err;
    }
    test::TempDir tmp_;
};

}  // namespace

TEST_F(CliOptions, OutputHasTheRequestedDimensions) {
    for (const char* file : {"a.exr", "a.png"}) {
        const CliRun r = run({"render", "-W", "17", "-H", "9", "-s", "1", "-o", out(file)});
        ASSERT_EQ(r.code, 0) << r.err;
    }
    const Image exr = readExr(out("a.exr"));
    EXPECT_EQ(exr.width, 17);
    EXPECT_EQ(exr.height, 9);
    const Png png = readPng(out("a.png"));
    EXPECT_EQ(png.width, 17u);
    EXPECT_EQ(png.height, 9u);
}

// The PNG is the EXR's radiance times --exposure, clamped and sRGB-encoded; the EXR ignores exposure.
TEST_F(CliOptions, ExposureScalesThePngAndNotTheExr) {
    render("plain.exr", {});
    render("exposed.exr", {"--exposure", "4"});
    EXPECT_EQ(readTextFile(out("plain.exr")), readTextFile(out("exposed.exr"))) << "--exposure must not touch EXR output";
    render("exposed.png", {"--exposure", "4"});
    render("plain.png", {});
    const Image linear = readExr(out("plain.exr"));
    const Png exposed = readPng(out("exposed.png")), plain = readPng(out("plain.png"));
    ASSERT_EQ(exposed.rgb.size(), linear.pixels.size() * 3);
    ASSERT_EQ(plain.rgb.size(), linear.pixels.size() * 3);
    std::size_t changed = 0;
    for (std::size_t i = 0; i < linear.pixels.size(); ++i)
        for (int c = 0; c < 3; ++c) {
            // The EXR holds float; the PNG was encoded from double: allow one code of rounding.
            const double v = linear.pixels[i][c];
            EXPECT_NEAR(exposed.rgb[3 * i + c], toSrgb8(v, 4.0), 1) << "pixel " << i << " channel " << c;
            EXPECT_NEAR(plain.rgb[3 * i + c], toSrgb8(v, 1.0), 1) << "pixel " << i << " channel " << c;
            changed += std::abs(int(exposed.rgb[3 * i + c]) - int(toSrgb8(v, 1.0))) > 1;
        }
    EXPECT_GT(changed, linear.pixels.size()) << "exposure 4 must brighten most channels";
}

TEST_F(CliOptions, ExrHalfWritesHalfChannelsAndFloatByDefault) {
    render("f.exr", {});
    render("h.exr", {"--exr-half"});
    const auto pixelTypes = [](const std::string& path) {
        Imf::InputFile file(path.c_str());
        std::vector<Imf::PixelType> types;
        for (auto it = file.header().channels().begin(); it != file.header().channels().end(); ++it) types.push_back(it.channel().type);
        return types;
    };
    const auto f = pixelTypes(out("f.exr")), h = pixelTypes(out("h.exr"));
    ASSERT_EQ(f.size(), 3u);
    ASSERT_EQ(h.size(), 3u);
    for (auto t : f) EXPECT_EQ(t, Imf::FLOAT);
    for (auto t : h) EXPECT_EQ(t, Imf::HALF);
    const Image a = readExr(out("f.exr")), b = readExr(out("h.exr"));
    ASSERT_EQ(a.pixels.size(), b.pixels.size());
    for (std::size_t i = 0; i < a.pixels.size(); ++i)
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(b.pixels[i][c], a.pixels[i][c], 1e-3 * a.pixels[i][c] + 1e-7);
}

TEST_F(CliOptions, DefaultOutputIsOutSlashSceneNamePng) {
    const fs::path before = fs::current_path();
    fs::current_path(tmp_.path);
    const CliRun r = run({"render", "-W", "12", "-H", "10", "-s", "1"});
    fs::current_path(before);
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("out/cornell.png"), std::string::npos) << r.out;
    const Png png = readPng(out("out/cornell.png"));
    EXPECT_EQ(png.width, 12u);
    EXPECT_EQ(png.height, 10u);
}

// --max-depth 0 shows emitters only (every pixel is 0 or at most the light's radiance, most are 0);
// each further bounce adds light.
TEST_F(CliOptions, MaxDepthLimitsTheBounces) {
    render("d0.exr", {"--max-depth", "0"});
    render("d1.exr", {"--max-depth", "1"});
    render("d3.exr", {"--max-depth", "3"});
    const Image d0 = readExr(out("d0.exr")), d1 = readExr(out("d1.exr")), d3 = readExr(out("d3.exr"));
    Scene cornell = makeCornellBox();
    double le = 0;
    for (const PhongMaterial& m : cornell.materials) le = std::max(le, maxComponent(m.emission));
    std::size_t lit = 0;
    for (const Color& c : d0.pixels) {
        EXPECT_LE(maxComponent(c), le * (1 + 1e-6));
        lit += maxComponent(c) > 0;
    }
    EXPECT_GT(lit, 0u) << "the light is in view";
    EXPECT_LT(lit, d0.pixels.size() / 10) << "only the light is lit at depth 0";
    std::size_t lit1 = 0;
    for (const Color& c : d1.pixels) lit1 += maxComponent(c) > 0;
    EXPECT_GT(lit1, d1.pixels.size() / 2) << "one bounce lights the walls";
    EXPECT_GT(meanOf(d1), 1.2 * meanOf(d0));
    EXPECT_GT(meanOf(d3), 1.1 * meanOf(d1)) << "interreflections add light";
}

// Without light sampling the renderer traces no shadow rays: a different image from the same seed
// (the library tests check that its mean is the same).
TEST_F(CliOptions, NoNeeChangesHowTheImageIsMade) {
    render("nee.exr", {"--max-depth", "1"});
    render("nonee.exr", {"--max-depth", "1", "--no-nee"});
    const Image a = readExr(out("nee.exr")), b = readExr(out("nonee.exr"));
    // Direct light only: with NEE nearly every floor pixel sees the light; without it, a pixel is lit
    // only when one of its 4 directions happens to hit the small light, so most pixels are darker
    // and a few much brighter.
    std::size_t darker = 0;
    for (std::size_t i = 0; i < a.pixels.size(); ++i) darker += luminance(b.pixels[i]) < luminance(a.pixels[i]);
    EXPECT_GT(darker, a.pixels.size() / 2);
}

// --paper-refined lowers the paper's lobe normalisation (Eq. 6 against the conclusion's: at n = 2,
// 0.73 against 0.81 of 2 pi/(n+1)), so with the same samples (and no Russian roulette, which depends on
// the weights) no pixel gets brighter and the glossy block gets darker.
TEST_F(CliOptions, PaperRefinedChangesThePapersLobeWeight) {
    // A low exponent: at n = 100 both normalisations are 2 pi/(n+1) to round-off.
    tmp_.write("low-n.json", R"({"builtin": "cornell", "materials": {"tallBlock": {"ns": 2}}})");
    render("p.exr", {out("low-n.json"), "-e", "paper", "--max-depth", "2"});
    render("r.exr", {out("low-n.json"), "-e", "paper", "--max-depth", "2", "--paper-refined"});
    const Image p = readExr(out("p.exr")), r = readExr(out("r.exr"));
    std::size_t darker = 0;
    for (std::size_t i = 0; i < p.pixels.size(); ++i)
        for (int c = 0; c < 3; ++c) {
            EXPECT_LE(r.pixels[i][c], p.pixels[i][c] * (1 + 1e-6) + 1e-9) << "pixel " << i;
            darker += r.pixels[i][c] < p.pixels[i][c] * (1 - 1e-4);
        }
    EXPECT_GT(darker, 10u);
}

// --symmetric-n sets the points per piece: N' = 2 traces twice the set's rays at the first hit.
TEST_F(CliOptions, SymmetricNReachesTheEstimator) {
    render("n1.exr", {"-e", "symmetric", "--max-depth", "1", "--no-nee"});
    render("n2.exr", {"-e", "symmetric", "--max-depth", "1", "--no-nee", "--symmetric-n", "2"});
    EXPECT_NE(readTextFile(out("n1.exr")), readTextFile(out("n2.exr")));
}

TEST_F(CliOptions, DifferentSeedsGiveDifferentImages) {
    render("s5.exr", {});
    const CliRun r = run({"render", "--seed", "6", "-W", "24", "-H", "20", "-s", "4", "-o", out("s6.exr")});
    ASSERT_EQ(r.code, 0) << r.err;
    const Image a = readExr(out("s5.exr")), b = readExr(out("s6.exr"));
    std::size_t differ = 0;
    for (std::size_t i = 0; i < a.pixels.size(); ++i) differ += !(a.pixels[i] == b.pixels[i]);
    EXPECT_GT(differ, a.pixels.size() / 2);
}

TEST_F(CliOptions, EverySceneInTheRepositoryRenders) {
    int count = 0;
    for (const auto& e : fs::directory_iterator(fs::path(SYMPHONG_SOURCE_DIR) / "scenes")) {
        if (e.path().extension() != ".json") continue;
        if (e.path().filename() == "mcguire-glossy.json" && test::scenesDir().empty()) continue;
        const std::string file = out(e.path().stem().string() + ".exr");
        const CliRun r = run({"render", e.path().string(), "-W", "12", "-H", "10", "-s", "2", "-o", file});
        ASSERT_EQ(r.code, 0) << e.path() << ": " << r.err;
        const Image img = readExr(file);
        EXPECT_EQ(img.width, 12);
        EXPECT_GT(meanOf(img), 0) << e.path() << " renders black";
        for (const Color& c : img.pixels) ASSERT_TRUE(std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z)) << e.path();
        ++count;
    }
    EXPECT_GE(count, 5);
}

// The progress bar draws on a terminal (here a pseudo-terminal) and ends at 100%; on a pipe it stays
// silent. The binary runs as a child process so that its stderr really is the terminal.
TEST_F(CliOptions, ProgressBarOnATerminalOnly) {
    const auto runChild = [&](bool terminal) {
        std::string output;
        int master = -1;
        int pipeFds[2] = {-1, -1};
        pid_t pid;
        if (terminal) {
            pid = forkpty(&master, nullptr, nullptr, nullptr);
        } else {
            if (pipe(pipeFds) != 0) return std::string("pipe failed");
            pid = fork();
        }
        if (pid < 0) return std::string("fork failed");
        if (pid == 0) {
            if (!terminal) {
                dup2(pipeFds[1], STDERR_FILENO);
                dup2(pipeFds[1], STDOUT_FILENO);
                close(pipeFds[0]);
            }
            const std::string file = out(terminal ? "tty.png" : "pipe.png");
            execl(SYMPHONG_BINARY, SYMPHONG_BINARY, "render", "-W", "64", "-H", "64", "-s", "16", "-o", file.c_str(),
                  static_cast<char*>(nullptr));
            _exit(127);
        }
        const int fd = terminal ? master : pipeFds[0];
        if (!terminal) close(pipeFds[1]);
        char buf[4096];
        for (;;) {
            const ssize_t n = read(fd, buf, sizeof buf);
            if (n <= 0) break;  // EOF, or EIO on the pty once the child has gone
            output.append(buf, static_cast<std::size_t>(n));
        }
        close(fd);
        int status = 0;
        waitpid(pid, &status, 0);
        EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << output;
        return output;
    };
    const std::string tty = runChild(true), piped = runChild(false);
    EXPECT_NE(tty.find("\r["), std::string::npos) << tty;
    EXPECT_NE(tty.find("100.0%"), std::string::npos) << tty;
    EXPECT_NE(tty.find("samples/s"), std::string::npos) << tty;
    EXPECT_EQ(piped.find('\r'), std::string::npos) << piped;
    EXPECT_EQ(piped.find("100.0%"), std::string::npos) << piped;
    EXPECT_NE(piped.find("Mrays/s"), std::string::npos) << piped;
}
