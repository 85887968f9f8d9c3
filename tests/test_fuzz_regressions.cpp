// The fuzzers' findings as regression tests (docs/reliability.md): every file under
// tests/data/fuzz/<target>/ goes through the same entry point as the fuzz target <target> (fuzz/
// fuzz_common.h: the same files written into a scratch directory, the same loader) and must either
// load, keeping the loader's promises (no NaN, no out-of-range index, valid texels), or be rejected
// with symphong::InputError. Any other exception fails the test; a crash or a sanitizer report ends the
// test binary; a hang runs into CTest's timeout. An empty or missing tests/data/fuzz fails too, so the
// suite cannot pass by finding nothing to run. tests/data/fuzz/third-party/ (findings inside libraries
// that symphong cannot prevent) is not run. Like the fuzz targets, the test compiles tinyobjloader's and
// stb_image's implementations in (fuzz/tinyobj_instrumented.cpp, fuzz/stb_image_instrumented.cpp), so
// that a sanitizer build (debug-asan) sees their faults too, not only symphong's.
#include "../fuzz/fuzz_common.h"
#include "accel/accel.h"
#include "estimators/registry.h"
#include "test_util.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <ostream>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <unistd.h>

namespace fs = std::filesystem;

namespace {

const fs::path kRoot = fs::path(SYMPHONG_SOURCE_DIR "/tests/data/fuzz");
const char* const kTargets[] = {"fuzz_obj",        "fuzz_json",     "fuzz_assimp",  "fuzz_texture",
                                "fuzz_ply",        "fuzz_checkpoint", "fuzz_settings", "fuzz_gltf_ext"};

struct Input {
    std::string target;
    fs::path file;
};

// How gtest names a parameter in its output: the target and the file (not the bytes of the struct).
void PrintTo(const Input& in, std::ostream* os) { *os << in.target << ": " << in.file.string(); }

std::vector<Input> inputs() {
    std::vector<Input> out;
    std::error_code ec;
    for (const char* target : kTargets) {
        const fs::path dir = kRoot / target;
        if (!fs::is_directory(dir, ec)) continue;
        for (const auto& e : fs::directory_iterator(dir, ec))
            if (e.is_regular_file()) out.push_back({target, e.path()});
    }
    std::sort(out.begin(), out.end(), [](const Input& a, const Input& b) { return a.file < b.file; });
    return out;
}

std::string readBytes(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// The same call as the fuzz target's; "" when it loads and keeps its promises or is rejected with
/// InputError, else what went wrong.
std::string verdict(const Input& in) {
    using namespace symphong::fuzz;
    const std::string bytes = readBytes(in.file);
    const fs::path dir = scratchDir("regression");
    try {
        std::string problemText;
        if (in.target == "fuzz_obj")
            problemText = problem(loadObjInput(dir, bytes));
        else if (in.target == "fuzz_json")
            problemText = problem(loadJsonInput(dir, bytes));
        else if (in.target == "fuzz_assimp")
            problemText = problem(loadAssimpInput(dir, bytes));
        else if (in.target == "fuzz_texture")
            problemText = problem(decodeTextureInput(bytes));
        else if (in.target == "fuzz_ply")
            problemText = problem(loadPlyInput(dir, bytes));
        else if (in.target == "fuzz_checkpoint")
            problemText = problem(readCheckpointInput(dir, bytes));
        else if (in.target == "fuzz_settings")
            problemText = problem(loadSettingsInput(dir, bytes));
        else if (in.target == "fuzz_gltf_ext")
            problemText = problem(loadGltfExtInput(dir, bytes));
        else
            return "unknown target " + in.target;
        return problemText.empty() ? "" : "accepted, but breaks the loader's promise: " + problemText;
    } catch (const symphong::InputError&) {
        return "";  // the expected rejection
    } catch (const std::exception& e) {
        return std::string("threw an exception other than InputError: ") + e.what();
    } catch (...) {
        return "threw something that is not a std::exception";
    }
}

class FuzzRegression : public ::testing::TestWithParam<Input> {};

}  // namespace

TEST(FuzzRegressions, DirectoryHoldsInputs) {
    ASSERT_TRUE(fs::is_directory(kRoot)) << kRoot << " is missing";
    EXPECT_FALSE(inputs().empty()) << "no files under " << kRoot << "/<target>/ (targets: fuzz_obj, fuzz_json, fuzz_assimp, fuzz_texture, fuzz_ply, fuzz_checkpoint, fuzz_settings, fuzz_gltf_ext)";
    // A file in a directory that names no target would never run (third-party/ holds findings inside
    // libraries that symphong cannot prevent, on purpose not run: its README.md says why).
    for (const auto& e : fs::directory_iterator(kRoot)) {
        if (e.is_directory() && e.path().filename() != "third-party") {
            EXPECT_NE(std::find(std::begin(kTargets), std::end(kTargets), e.path().filename().string()), std::end(kTargets))
                << e.path() << " is not the directory of a fuzz target";
        }
    }
}

TEST_P(FuzzRegression, LoadsOrIsRejectedWithInputError) {
    const Input& in = GetParam();
    const std::string v = verdict(in);
    EXPECT_TRUE(v.empty()) << in.file.string() << " (" << in.target << "): " << v;
}

INSTANTIATE_TEST_SUITE_P(Findings, FuzzRegression, ::testing::ValuesIn(inputs()), [](const ::testing::TestParamInfo<Input>& info) {
    std::string name = info.param.target + "_" + info.param.file.filename().string();
    for (char& c : name)
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
    return name;
});
GTEST_ALLOW_UNINSTANTIATED_PARAMETERIZED_TEST(FuzzRegression);

// The findings inside Assimp itself (third-party/, its README): since Assimp's importers run first in a
// child process (scene/assimp_guard.cpp), a crash or a runaway allocation in Assimp is an InputError that
// names the file and says what happened, from loadScene as from the command line (exit code 2, one line).
TEST(ThirdPartyFindings, CrashesInsideAssimpAreInputErrors) {
    using namespace symphong;
    const fs::path dir = fs::temp_directory_path() / ("symphong-third-party-" + std::to_string(::getpid()));
    std::vector<std::pair<const char*, const char*>> cases = {
        {"segv-collada-polylist-without-inputs.dae", "crashed"},
        {"segv-collada-null-read-exported-box.dae", "crashed"},
        {"stack-overflow-fbx-recursion.fbx", "crashed"},
    };
#if !defined(__SANITIZE_ADDRESS__)  // the child's address-space limit needs a build without ASan's shadow memory
    cases.push_back({"oom-collada-20-GB-48-s-from-8.8-KB.dae", "in.dae: "});
#endif
    fs::create_directories(dir);
    for (const auto& [file, expected] : cases) {
        const std::string bytes = readBytes(kRoot / "third-party" / "fuzz_assimp" / file);
        try {
            fuzz::loadAssimpInput(dir, bytes);
            ADD_FAILURE() << file << " loaded";
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << file << ": " << e.what();
        }
    }
    // The command line: exit code 2 and one line naming the file.
    const std::string bytes = readBytes(kRoot / "third-party" / "fuzz_assimp" / "segv-collada-polylist-without-inputs.dae");
    const fs::path crash = dir / "crash.dae";
    std::ofstream(crash, std::ios::binary) << bytes.substr(1);  // past the fuzz input's extension byte
    const auto run = test::runCliArgs({"info", crash.string()});
    EXPECT_EQ(run.code, 2);
    EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
    EXPECT_NE(run.err.find("crash.dae: Assimp"), std::string::npos) << run.err;
    std::error_code ec;
    fs::remove_all(dir, ec);
}

// Finding C1 (fuzz_checkpoint): a header number outside its type (rays 1e30 read as a 64-bit count,
// width 4e9 read as an int) was converted anyway: undefined behaviour that clang's UBSan reports and
// that a release build turns into whatever count the conversion gives. The generic replay above cannot
// tell such a file from a good one where UBSan does not check float-to-integer conversions (gcc's
// -fsanitize=undefined leaves them out), so here: each is refused with InputError naming the file, the
// key and the value.
TEST(FuzzRegressions, C1CheckpointHeaderNumbersOutsideTheirTypesAreRefused) {
    using namespace symphong;
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"header-rays-1e30-outside-uint64.ckpt", "its header's rays is 1e+30"},
        {"header-width-4e9-outside-int.ckpt", "its header's width is 4000000000.0"},
    };
    const fs::path dir = fuzz::scratchDir("regression");
    for (const auto& [file, expected] : cases) {
        const std::string bytes = readBytes(kRoot / "fuzz_checkpoint" / file);
        try {
            fuzz::readCheckpointInput(dir, bytes);
            ADD_FAILURE() << file << " was accepted";
        } catch (const InputError& e) {
            const std::string what = e.what();
            EXPECT_NE(what.find("in.ckpt: not a usable checkpoint"), std::string::npos) << file << ": " << what;
            EXPECT_NE(what.find(expected), std::string::npos) << file << ": " << what;
        }
    }
}

// Finding C2 (fuzz_checkpoint, with the harness making the checksum right): a checkpoint whose sums are
// not finite, or whose sums of squares are negative, was accepted, and a resumed render would have
// carried them into its image, variance and error. Refused, naming the pixel.
TEST(FuzzRegressions, C2CheckpointSumsThatNoRenderWritesAreRefused) {
    using namespace symphong;
    const std::string bytes = readBytes(kRoot / "fuzz_checkpoint" / "sums-not-finite-under-a-matching-checksum.ckpt");
    try {
        fuzz::readCheckpointInput(fuzz::scratchDir("regression"), bytes);
        ADD_FAILURE() << "accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("holds a sum that no render writes"), std::string::npos) << e.what();
    }
}

namespace {

/// A checkpoint as writeCheckpoint writes it: 16 x 12 pixels of the built-in Cornell box, stopped at 5 of
/// 16 samples; with --splitting ears inside epoch 2, its factors learned from epoch 1 and its sums begun.
std::string writtenCheckpoint(bool ears) {
    using namespace symphong;
    const Scene scene = loadScene("cornell");
    const Accel accel(scene);
    const auto est = makeEstimator("phong");
    RenderSettings rs;
    rs.width = 16, rs.height = 12, rs.spp = 16, rs.seed = 3, rs.threads = 1;
    if (ears) rs.trace.splitting = SplittingMode::Ears;
    RenderState state(rs.width, rs.height, rs.spp);
    probeLearning(scene, accel, *est, rs, state);
    renderSamples(scene, accel, *est, rs, state, 5);
    const test::TempDir tmp;
    const std::string path = tmp.file("written.ckpt");
    writeCheckpoint(path, RenderIdentity{"cornell", "0123456789abcdef", nlohmann::json::object()}, state);
    return readBytes(path);
}

/// A checkpoint's header line (after the magic line) and the offset just past it.
nlohmann::json headerLine(const std::string& file, std::size_t& end) {
    const std::size_t from = symphong::fuzz::kCheckpointMagic.size();
    end = file.find('\n', from) + 1;
    return nlohmann::json::parse(file.substr(from, end - from));
}

/// The checkpoint's offset of its first section after the pixel sections (the learned splitting's factor
/// cells): the header line's end plus the tile counts and the three sums of every pixel.
std::size_t earsSectionsStart(const std::string& file) {
    std::size_t start = 0;
    const nlohmann::json header = headerLine(file, start);
    const int w = header.at("width"), h = header.at("height");
    return start + static_cast<std::size_t>(symphong::tileCount(w, h)) * 4 + static_cast<std::size_t>(w * h) * (24 + 24 + 8);
}

}  // namespace

// The harness's checksum repair (fuzz_common.h withFixedChecksum) against the writer's own checksum: a
// checkpoint as writeCheckpoint wrote it, its checksum zeroed, comes back byte for byte. A plain render's,
// a --splitting ears one's (four sections of learned splitting after the pixels, four values a factor cell)
// and the committed one of an older build (three values a cell, no factor_values key). Without the ears
// sections the fuzzer's mutations of them stopped at the checksum.
TEST(FuzzHarness, ChecksumRepairGivesTheWritersChecksum) {
    std::vector<std::pair<std::string, std::string>> files = {{"plain", writtenCheckpoint(false)}, {"ears", writtenCheckpoint(true)}};
    files.emplace_back("ears, three values", readBytes(SYMPHONG_SOURCE_DIR "/tests/data/checkpoints/ears-three-values.ckpt"));
    for (const auto& [name, file] : files) {
        ASSERT_GT(file.size(), 8u) << name;
        std::string zeroed = file;
        std::memset(zeroed.data() + zeroed.size() - 8, 0, 8);
        ASSERT_TRUE(zeroed != file) << name;
        EXPECT_TRUE(symphong::fuzz::withFixedChecksum(zeroed) == file) << name << ": not the bytes the writer wrote";  // not a dump of them
        EXPECT_EQ(file.find("\"ears\"") != std::string::npos, name != "plain") << name;
    }
    // The ears checkpoint holds what the test is about: factor cells and sums after the pixel sections.
    const std::string& ears = files[1].second;
    EXPECT_GT(ears.size(), earsSectionsStart(ears) + 8 + 1000) << "an ears checkpoint with hardly any learned splitting";
}

// Found by reading, once the harness could repair the checksum of the learned splitting's sections: the
// reader took any float as a factor, and a resumed render multiplied it into its decisions (an infinite MIS
// share turns the first hit's light samples into NaN, discarded as bad). A factor that learnFactors cannot
// give is refused, naming its value and cell; every value it can give is accepted (the written checkpoint
// itself, and the same one with a factor at the ends of its range).
TEST(FuzzRegressions, C3CheckpointFactorsThatNoRenderWritesAreRefused) {
    using namespace symphong;
    const std::string file = writtenCheckpoint(true);
    std::size_t headerEnd = 0;
    const std::size_t cells = headerLine(file, headerEnd).at("ears").at("factor_cells");
    ASSERT_GT(cells, 0u);
    // The first factor cell's values (Factors::tables' order: varianceRatio, momentRatio, firstHit, misShare).
    const std::size_t values = earsSectionsStart(file) + cells * 4;
    const auto withValue = [&](std::size_t k, float v) {
        std::string f = file;
        std::memcpy(f.data() + values + 4 * k, &v, 4);
        return std::string(1, '\x01') + f;  // flags: the harness makes the checksum right
    };
    const fs::path dir = fuzz::scratchDir("regression");
    const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
    const std::vector<std::tuple<std::size_t, float, std::string>> refused = {
        {0, nan, "nan"}, {1, inf, "inf"}, {0, -0.5f, "-0.5"}, {2, 0.5f, "0.5"}, {2, 9.0f, "9"}, {3, 1.5f, "1.5"}, {3, inf, "inf"}};
    for (const auto& [k, v, text] : refused) {
        try {
            fuzz::readCheckpointInput(dir, withValue(k, v));
            ADD_FAILURE() << "value " << text << " of table " << k << " was accepted";
        } catch (const InputError& e) {
            const std::string what = e.what();
            EXPECT_NE(what.find("holds a factor that no render writes: " + text + " in cell"), std::string::npos) << what;
        }
    }
    const std::vector<std::pair<std::size_t, float>> accepted = {{0, 0.0f}, {1, 1e30f}, {2, 1.0f}, {2, 8.0f},
                                                                 {3, 0.0f}, {3, 1.0f},  {3, -1.0f}};
    for (const auto& [k, v] : accepted) {
        const auto read = fuzz::readCheckpointInput(dir, withValue(k, v));
        EXPECT_EQ(fuzz::checkpointProblem(read), "") << "value " << v << " of table " << k;
    }
    EXPECT_EQ(fuzz::checkpointProblem(fuzz::readCheckpointInput(dir, std::string(1, '\0') + file)), "");
}
