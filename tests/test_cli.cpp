// The command line end to end (in process): every bad input gives a one-line message naming the
// problem, exit code 2, and leaves no output file (an existing one is left untouched); good inputs
// render every shared scene.
#include "cli/cli.h"
#include "io/files.h"
#include "test_util.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <set>

using namespace symphong;
namespace fs = std::filesystem;

namespace {

using test::CliRun;

CliRun runArgs(std::vector<std::string> args) { return test::runCliArgs(std::move(args)); }

class Cli : public ::testing::Test {
protected:
    std::string out(const std::string& name) const { return tmp_.file(name); }
    std::string write(const std::string& name, const std::string& text) const { return tmp_.write(name, text); }
    /// Nothing but the files we put there: no image, no temporary file.
    std::size_t filesInDir() const {
        std::size_t n = 0;
        for ([[maybe_unused]] const auto& e : fs::directory_iterator(tmp_.path)) ++n;
        return n;
    }
    void expectBadInput(const std::vector<std::string>& args, const std::string& expected) {
        const std::size_t before = filesInDir();
        const CliRun r = runArgs(args);
        EXPECT_EQ(r.code, 2) << r.err;
        EXPECT_NE(r.err.find(expected), std::string::npos) << "stderr was: " << r.err;
        EXPECT_NE(r.err.find("error"), std::string::npos) << r.err;
        // One line: the message and nothing else (no usage dump, no second line).
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << "stderr was: " << r.err;
        EXPECT_TRUE(!r.err.empty() && r.err.back() == '\n') << r.err;
        EXPECT_EQ(filesInDir(), before) << "a failed run must not create files: " << r.err;
    }
    test::TempDir tmp_;
};

}  // namespace

TEST_F(Cli, HelpExitsZeroAndExplains) {
    const CliRun r = runArgs({"render", "--help"});
    EXPECT_EQ(r.code, 0);
    EXPECT_NE(r.out.find("--estimator"), std::string::npos);
    EXPECT_NE(r.out.find("sRGB"), std::string::npos);
    EXPECT_NE(r.out.find("--exposure"), std::string::npos);
}

TEST_F(Cli, InfoPrintsWhatWasLoaded) {
    const CliRun r = runArgs({"info"});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("scene       cornell (from cornell)"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("triangles   32 (2 emissive), 64 vertices"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("'tallBlock'          rho_d (0.3, 0.3, 0.3)  rho_s (0.45, 0.45, 0.45)  n 60"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("emission (17, 12, 4)  (2 triangles)"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("camera      position (278, 273, -800)"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("environment constant radiance (0, 0, 0)"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("warnings    0"), std::string::npos) << r.out;
    { std::ofstream(out("floor.obj")) << "v -1 0 -1\nv -1 0 1\nv 1 0 1\nv 1 0 -1\nf 1 2 3 4\n"; }
    {
        std::ofstream(out("spot.json"))
            << R"({"obj": "floor.obj", "lights": [{"type": "spot", "position": [0, 1, 0], "target": [0, 0, 0], "intensity": 2, "angle": 40, "inner": 30}]})";
    }
    const CliRun spot = runArgs({"info", out("spot.json")});
    ASSERT_EQ(spot.code, 0) << spot.err;
    EXPECT_NE(spot.out.find("  spot        position (0, 1, 0), direction (0, -1, 0), intensity (2, 2, 2), cone 30 to 40 degrees"),
              std::string::npos)
        << spot.out;
    const CliRun bare = runArgs({"info", out("floor.obj")});
    ASSERT_EQ(bare.code, 0) << bare.err;
    EXPECT_NE(bare.out.find("environment default sky"), std::string::npos) << bare.out;
    EXPECT_NE(bare.out.find("  directional direction"), std::string::npos) << bare.out;
    EXPECT_NE(bare.out.find("warnings    1"), std::string::npos) << bare.out;
    expectBadInput({"info", out("missing.obj")}, "no such file");
}

TEST_F(Cli, InfoListsTexturesMapsAndTheEnvironmentMap) {
    const CliRun r = runArgs({"info", std::string(SYMPHONG_SOURCE_DIR) + "/scenes/textured.json"});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("environment HDR map "), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("sky.hdr (512 x 256), scale 1, rotation 0 degrees, bilinear filtering"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("textures    5 ("), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("64 x 64, 3 channels, wrap repeat/repeat: "), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("128 x 128, 1 channel, wrap repeat/repeat: "), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("maps: rho_d = texture 2, rho_s = texture 3 (times the constants above)"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("maps: cut-out = texture 4"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("warnings    0"), std::string::npos) << r.out;
}

TEST_F(Cli, RendersTheDefaultSceneToPngAndExr) {
    const CliRun png = runArgs({"render", "--spp", "2", "-W", "16", "-H", "12", "-o", out("c.png")});
    ASSERT_EQ(png.code, 0) << png.err;
    EXPECT_TRUE(fs::file_size(out("c.png")) > 0);
    EXPECT_NE(png.out.find("Mrays/s"), std::string::npos) << png.out;
    EXPECT_NE(png.out.find("samples/s"), std::string::npos) << png.out;
    const CliRun exr = runArgs({"render", "cornell", "--spp", "1", "-W", "8", "-H", "8", "--exr-half", "-o", out("c.exr")});
    ASSERT_EQ(exr.code, 0) << exr.err;
    EXPECT_EQ(filesInDir(), 2u) << "no temporary files are left behind";
}

TEST_F(Cli, BadArgumentsAreRejected) {
    expectBadInput({"render", "--estimator", "symetric", "-o", out("a.png")}, "valid: uniform, cosine, stratified, phong");
    expectBadInput({"render", "--spp", "0", "-o", out("a.png")}, "--spp");
    expectBadInput({"render", "--spp", "-4", "-o", out("a.png")}, "--spp");
    expectBadInput({"render", "--width", "0", "-o", out("a.png")}, "--width");
    expectBadInput({"render", "--height", "100000", "-o", out("a.png")}, "--height");
    expectBadInput({"render", "--width", "16384", "--height", "16384", "-o", out("a.png")}, "too large");
    expectBadInput({"render", "--exposure", "-1", "-o", out("a.png")}, "--exposure");
    expectBadInput({"render", "--max-depth", "-1", "-o", out("a.png")}, "--max-depth");
    expectBadInput({"render", "--spp", "abc", "-o", out("a.png")}, "abc");
    expectBadInput({"render", "-o", out("a.jpg")}, "must end in .png or .exr");
    expectBadInput({"render", "--bogus"}, "--bogus");
    expectBadInput({}, "subcommand");
}

TEST_F(Cli, BadScenesAreRejected) {
    expectBadInput({"render", out("missing.obj"), "-o", out("a.png")}, "missing.obj: no such file");
    expectBadInput({"render", "scene.blend", "-o", out("a.png")}, "unknown scene");
    expectBadInput(
        {"render", write("bad.json", "{\"builtin\": \"cornell\", \"materials\": {\"white\": {\"ns\": -2}}}"), "-o", out("a.png")},
        "negative");
    expectBadInput({"render", write("nan.json", "{\"builtin\": \"cornell\", \"environment\": NaN}"), "-o", out("a.png")}, "malformed JSON");
}

TEST_F(Cli, EveryMalformedObjExitsTwoAndWritesNothing) {
    SYMPHONG_REQUIRE_SCENES_DIR();
    int files = 0;
    for (const auto& e : fs::directory_iterator(test::scenesDir() + "/malformed"))
        if (e.path().extension() == ".obj") {
            // The message names the file, and the line where the format has one: "name.obj:LINE:".
            expectBadInput({"render", e.path().string(), "--spp", "1", "-W", "8", "-H", "8", "-o", out("m.png")},
                           e.path().filename().string() + ":");
            ++files;
        }
    EXPECT_EQ(files, 5) << "the shared scenes' malformed/ holds five OBJ files";
}

// A JSON scene's syntax error names file:line:column; a semantic one the element's path.
TEST_F(Cli, MalformedJsonNamesTheLineOrTheElement) {
    expectBadInput({"render", write("syntax.json", "{\n  \"builtin\": \"cornell\",\n  \"environment\": 0.5,,\n}\n"), "-o", out("a.png")},
                   "syntax.json:3:");
    expectBadInput(
        {"render", write("neg.json", "{\"builtin\": \"cornell\", \"materials\": {\"white\": {\"ns\": -2}}}"), "-o", out("a.png")},
        "materials.white.ns");
}

TEST_F(Cli, AFailedRunLeavesAnExistingOutputUntouched) {
    const std::string target = write("keep.png", "previous contents");
    const CliRun r = runArgs({"render", "--estimator", "nope", "-o", target});
    EXPECT_EQ(r.code, 2);
    EXPECT_EQ(readTextFile(target), "previous contents");
}

TEST_F(Cli, UnwritableOutputIsAnErrorBeforeRendering) {
    write("file", "x");
    const CliRun r = runArgs({"render", "--spp", "1", "-W", "4", "-H", "4", "-o", out("file") + "/sub/a.png"});
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.err.find("cannot create"), std::string::npos) << r.err;
}

TEST_F(Cli, RendersEverySharedSceneThatIsNotMalformed) {
    SYMPHONG_REQUIRE_SCENES_DIR();
    const std::vector<std::pair<std::string, std::string>> scenes = {
        {"cornell-box-mcguire/CornellBox-Original.obj", ""},         {"cornell-box-mcguire/CornellBox-Glossy.obj", "'sphere'"},
        {"cornell-box-mcguire/CornellBox-Sphere.obj", ""},           {"cornell-box-original/cornell_box.obj", "no light of any kind"},
        {"lenient/missing_material_file.obj", "undefined material"}, {"bunny/stanford-bunny.obj", "default sky"},
    };
    for (const auto& [rel, warning] : scenes) {
        const std::string png = out(fs::path(rel).stem().string() + ".png");
        const CliRun r = runArgs({"render", test::scenesDir() + "/" + rel, "--spp", "2", "-W", "16", "-H", "16", "-o", png});
        EXPECT_EQ(r.code, 0) << rel << ": " << r.err;
        EXPECT_TRUE(fs::exists(png)) << rel;
        if (!warning.empty()) {
            EXPECT_NE(r.err.find(warning), std::string::npos) << rel << ": " << r.err;
        }
    }
}

TEST_F(Cli, RendersWithTheSymmetricEstimators) {
    for (const char* e : {"symmetric", "symmetric-shifted", "paper"}) {
        const CliRun r =
            runArgs({"render", "-e", e, "--symmetric-n", "2", "--spp", "1", "-W", "8", "-H", "8", "-o", out(std::string(e) + ".png")});
        EXPECT_EQ(r.code, 0) << e << ": " << r.err;
    }
    expectBadInput({"render", "-e", "symmetric", "--symmetric-n", "0", "-o", out("a.png")}, "--symmetric-n");
}

TEST_F(Cli, FurnacePrintsATableAndWritesJson) {
    const CliRun r = runArgs({"furnace", "-e", "cosine,symmetric", "--environment", "constant,disk", "--n", "1,100", "--theta", "0,60",
                              "-M", "200", "--json", out("f.json")});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("symmetric"), std::string::npos);
    EXPECT_NE(r.out.find("var x dirs"), std::string::npos);
    const std::string json = readTextFile(out("f.json"));
    std::size_t rows = 0;
    for (std::size_t p = json.find("\"estimator\""); p != std::string::npos; p = json.find("\"estimator\"", p + 1)) ++rows;
    EXPECT_EQ(rows, 2u * 2 * 2 * 2);
    for (const char* key : {"\"exact\"", "\"relative_bias\"", "\"z\"", "\"variance_times_directions\"", "\"seconds_per_estimate\""})
        EXPECT_NE(json.find(key), std::string::npos) << key;
}

// --grid runs n in {1, 10, 100, 1000, 10000} x theta in {0, 30, 60, 85}: 20 rows per estimator and
// environment, with exactly those values.
TEST_F(Cli, FurnaceGridCoversItsCells) {
    const CliRun r = runArgs({"furnace", "-e", "cosine", "--environment", "constant", "--grid", "-M", "4", "--json", out("g.json")});
    ASSERT_EQ(r.code, 0) << r.err;
    const auto rows = nlohmann::json::parse(readTextFile(out("g.json")));
    ASSERT_EQ(rows.size(), 20u);
    std::set<std::pair<double, double>> cells;
    for (const auto& row : rows) cells.insert({row["n"].get<double>(), row["theta_deg"].get<double>()});
    for (double n : {1.0, 10.0, 100.0, 1000.0, 10000.0})
        for (double theta : {0.0, 30.0, 60.0, 85.0}) EXPECT_TRUE(cells.count({n, theta})) << "n " << n << " theta " << theta;
}

TEST_F(Cli, FurnaceRejectsBadInput) {
    expectBadInput({"furnace", "-e", "cosin"}, "unknown name 'cosin'");
    expectBadInput({"furnace", "--environment", "sky"}, "unknown name 'sky'");
    expectBadInput({"furnace", "--n", "-1"}, "--n");
    expectBadInput({"furnace", "--theta", "90"}, "--theta");
    expectBadInput({"furnace", "--rho-d", "1.5"}, "--rho-d");
    expectBadInput({"furnace", "-M", "1"}, "--repeats");
    fs::create_directories(tmp_.path / "adir");
    expectBadInput({"furnace", "-M", "10", "--json", out("adir")}, "adir: is a directory");
    write("afile", "x");
    expectBadInput({"furnace", "-M", "10", "--json", out("afile") + "/sub/f.json"}, "afile/sub: ");
}

// The sampler options: names checked, every sampler renders, --seed and --threads through the CLI give
// the same EXR bit for bit, and the summary names the sampler actually used.
TEST_F(Cli, SamplerOptions) {
    expectBadInput({"render", "--sampler", "halton", "-W", "8", "-H", "8", "-o", out("x.png")}, "halton");
    expectBadInput({"render", "--symmetric-mode", "sideways", "-W", "8", "-H", "8", "-o", out("x.png")}, "sideways");
    expectBadInput({"study", "--samplers", "sobol,halton", "-W", "8", "-H", "8", "-o", out("st")}, "halton");
    expectBadInput({"study", "--symmetric-modes", "branch,fan", "-W", "8", "-H", "8", "-o", out("st")}, "fan");
    std::string first;
    for (const char* sampler : {"independent", "stratified", "sobol"}) {
        for (const char* threads : {"1", "3"}) {
            const std::string file = out(std::string(sampler) + threads + ".exr");
            const CliRun r = runArgs({"render", "--sampler", sampler, "--threads", threads, "--seed", "9", "-W", "20", "-H", "18", "-s",
                                      "3", "-e", "symmetric", "--symmetric-mode", "spread", "-o", file});
            ASSERT_EQ(r.code, 0) << r.err;
            EXPECT_NE(r.out.find(std::string("sampler ") + sampler), std::string::npos) << r.out;
            const std::string bytes = readTextFile(file);
            if (std::string(threads) == "1")
                first = bytes;
            else
                EXPECT_EQ(first, bytes) << sampler << ": --threads 3 must give the bytes of --threads 1";
        }
    }
    // `stratified` is cosine under the stratified sampler, whatever --sampler says.
    const CliRun r = runArgs({"render", "-e", "stratified", "--sampler", "sobol", "-W", "8", "-H", "8", "-s", "2", "-o", out("s.png")});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("sampler stratified"), std::string::npos) << r.out;
}
