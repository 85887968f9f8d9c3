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
#include "test_util.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <ostream>
#include <string>
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
