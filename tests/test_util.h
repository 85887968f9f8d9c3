// Shared helpers for tests that need scenes: where the shared test scenes are, a closed furnace
// sphere, and tiny renders.
#pragma once

#include "accel/accel.h"
#include "cli/cli.h"
#include "estimators/estimator.h"
#include "render/renderer.h"
#include "scene/scene.h"
#include "compare/metrics.h"

#include <gtest/gtest.h>

#include <unistd.h>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

namespace symphong::test {

/// True in the sanitizer build (debug-asan: SYMPHONG_TEST_SANITIZED, set by tests/CMakeLists.txt), where
/// code runs 10 to 50 times slower: statistical tests that loop over many configurations run a subset
/// of them there (every code path still, each configuration at its full sample count and so its full
/// power), so that the sanitizers see the code without the CI run outgrowing its time.
#if defined(SYMPHONG_TEST_SANITIZED)
inline constexpr bool kSanitized = true;
#else
inline constexpr bool kSanitized = false;
#endif

/// ../shared/scenes beside the repository, or $SYMPHONG_SCENES. Empty when absent.
inline std::string scenesDir() {
    if (const char* env = std::getenv("SYMPHONG_SCENES")) return env;
    return std::filesystem::exists(SYMPHONG_SHARED_SCENES) ? std::string(SYMPHONG_SHARED_SCENES) : std::string();
}

/// Skips the test when the shared scenes are missing, unless SYMPHONG_REQUIRE_SCENES is set (CI sets it).
#define SYMPHONG_REQUIRE_SCENES_DIR()                                                              \
    do {                                                                                           \
        if (::symphong::test::scenesDir().empty()) {                                               \
            if (std::getenv("SYMPHONG_REQUIRE_SCENES")) FAIL() << "shared scenes not found";       \
            GTEST_SKIP() << "shared scenes not found beside the repository (set SYMPHONG_SCENES)"; \
        }                                                                                          \
    } while (0)

/// A fresh directory for one test, named after it (suite and test, so binaries run side by side do
/// not share it), removed when the test ends.
struct TempDir {
    std::filesystem::path path;
    TempDir() {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        // The process id too: two test suites (two builds) may run at once on one machine.
        path = std::filesystem::temp_directory_path() /
               ("symphong-test-" + std::string(info->test_suite_name()) + "." + info->name() + "." + std::to_string(::getpid()));
        std::filesystem::remove_all(path);
        std::filesystem::create_directories(path);
    }
    ~TempDir() { std::filesystem::remove_all(path); }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
    /// The path of `name` inside the directory.
    std::string file(const std::string& name) const { return (path / name).string(); }
    /// Writes `text` to `name` inside the directory; returns its path.
    std::string write(const std::string& name, const std::string& text) const {
        std::ofstream(path / name) << text;
        return file(name);
    }
};

/// Adds a closed UV sphere of radius 1 at the origin with `material`, its triangles wound so that their
/// counter-clockwise normals point outwards (or inwards).
inline void addUvSphere(Scene& s, std::uint32_t material, bool outwards, int stacks = 16, int slices = 32) {
    const auto base = static_cast<std::uint32_t>(s.positions.size());
    for (int i = 0; i <= stacks; ++i)
        for (int j = 0; j < slices; ++j) {
            const double th = kPi * i / stacks, ph = kTwoPi * j / slices;
            s.positions.emplace_back(std::sin(th) * std::cos(ph), std::cos(th), std::sin(th) * std::sin(ph));
        }
    const auto at = [&](int i, int j) { return base + static_cast<std::uint32_t>(i * slices + (j % slices)); };
    const auto add = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
        s.triangles.push_back(
            {outwards ? std::array<std::uint32_t, 3>{a, c, b} : std::array<std::uint32_t, 3>{a, b, c}, {-1, -1, -1}, material});
    };
    for (int i = 0; i < stacks; ++i)
        for (int j = 0; j < slices; ++j) {
            if (i > 0) add(at(i, j), at(i + 1, j), at(i, j + 1));
            if (i + 1 < stacks) add(at(i, j + 1), at(i + 1, j), at(i + 1, j + 1));
        }
}

/// A closed UV sphere of radius 1 seen from inside: every triangle faces the centre, emits Le and
/// reflects diffusely with albedo a. The radiance everywhere inside is Le / (1 - a).
inline Scene makeFurnaceSphere(double le, double albedo, int stacks = 16, int slices = 32) {
    Scene s;
    s.name = "furnace";
    PhongMaterial m;
    m.name = "furnace";
    m.rhoD = Color(albedo);
    m.emission = Color(le);
    s.materials.push_back(m);
    addUvSphere(s, 0, false, stacks, slices);
    s.camera.position = Vec3(0.1, -0.05, 0.02);
    s.camera.target = Vec3(1, 0.2, 0.3);
    s.camera.up = Vec3(0, 1, 0);
    s.camera.fovY = 90;
    return s;
}

/// Two triangles (a, b, c) and (a, c, d) of `material`: a planar quad whose front faces along
/// cross(b - a, c - a) (an emitter emits on that side).
inline void addQuad(Scene& s, Vec3 a, Vec3 b, Vec3 c, Vec3 d, std::uint32_t material) {
    const auto base = static_cast<std::uint32_t>(s.positions.size());
    for (const Vec3& v : {a, b, c, d}) s.positions.push_back(v);
    s.triangles.push_back({{base, base + 1, base + 2}, {-1, -1, -1}, material});
    s.triangles.push_back({{base, base + 2, base + 3}, {-1, -1, -1}, material});
}

/// A render's mean luminance over the whole image and its standard error (pixels are independent
/// under the independent sampler, so the variances of their means add).
inline std::pair<double, double> imageMeanAndError(const RenderResult& r) {
    double m = 0, v = 0;
    for (std::size_t i = 0; i < r.image.pixels.size(); ++i) m += luminance(r.image.pixels[i]), v += luminanceVariance(r.variance.pixels[i]);
    const double n = static_cast<double>(r.image.pixels.size());
    return {m / n, std::sqrt(v) / n};
}

inline RenderResult renderTiny(const Scene& scene, const std::string& estimator, int size, std::uint32_t spp, std::uint64_t seed,
                               int threads = 0, bool nee = true, int maxDepth = 16,
                               const std::string& sampler = std::string(kDefaultSampler)) {
    const Accel accel(scene);
    const auto est = makeEstimator(estimator);
    RenderSettings rs;
    rs.width = rs.height = size;
    rs.spp = spp;
    rs.seed = seed;
    rs.sampler = sampler;
    rs.threads = threads;
    rs.trace.nextEvent = nee;
    rs.trace.maxDepth = maxDepth;
    return render(scene, accel, *est, rs);
}

/// A render under the independent sampler (whose pixels are independent, as imageMeanAndError needs).
inline RenderResult renderIndependent(const Scene& s, const std::string& estimator, int size, std::uint32_t spp, std::uint64_t seed,
                                      bool nee = true) {
    return renderTiny(s, estimator, size, spp, seed, 0, nee, RenderSettings{}.trace.maxDepth, "independent");
}

/// The command line run in process, with its exit code and captured output.
struct CliRun {
    int code;
    std::string err, out;
};

/// Whether two images hold the same pixels bit for bit.
inline bool sameBits(const Image& a, const Image& b) {
    return a.pixels.size() == b.pixels.size() && std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(Color)) == 0;
}

inline CliRun runCliArgs(std::vector<std::string> args) {
    args.insert(args.begin(), "symphong");
    std::vector<const char*> argv;
    for (const auto& a : args) argv.push_back(a.c_str());
    testing::internal::CaptureStderr();
    testing::internal::CaptureStdout();
    const int code = runCli(static_cast<int>(argv.size()), argv.data());
    std::string err = testing::internal::GetCapturedStderr();
    return {code, err, testing::internal::GetCapturedStdout()};
}

}  // namespace symphong::test
