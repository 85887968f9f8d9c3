// Settings described once (util/schema.h; render/settings, study/config, estimators/options): the
// schemas' defaults against the renderer's and the study's own defaults (a second source), JSON written
// and read back, its errors naming the key, the command-line options built from a schema parsing and
// checking as CLI11 does, and a study's settings in results.json giving its configuration back.
#include "cli/schema_cli.h"
#include "estimators/options.h"
#include "io/input_error.h"
#include "render/settings.h"
#include "scene/scene.h"
#include "study/config.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <set>

#include <unistd.h>

using namespace symphong;

namespace {

template <class S>
void expectUniqueNames(const schema::Schema<S>& fields) {
    std::set<std::string> keys, pyKeys, flags;
    for (const auto& f : fields) {
        EXPECT_TRUE(keys.insert(f.key).second) << f.key;
        EXPECT_FALSE(f.help.empty()) << f.key;
        if (f.in(schema::kPython)) {
            EXPECT_TRUE(pyKeys.insert(f.pyKey()).second) << f.pyKey();
        }
        if (!f.in(schema::kCli)) continue;
        for (std::size_t start = 0; start < f.flags.size();) {
            const std::size_t comma = f.flags.find(',', start);
            EXPECT_TRUE(flags.insert(f.flags.substr(start, comma - start)).second) << f.flags;
            start = comma == std::string::npos ? f.flags.size() : comma + 1;
        }
    }
}

}  // namespace

TEST(Schema, NamesAreUniqueAndEveryFieldIsExplained) {
    expectUniqueNames(renderSchema());
    expectUniqueNames(studySchema());
    expectUniqueNames(furnaceSchema());
    expectUniqueNames(estimatorOptionsSchema());
}

TEST(Schema, RenderDefaultsAreTheRenderersOwn) {
    const RenderSettings fromSchema = renderSettings(RenderOptions{});
    const RenderSettings renderer;  // the renderer's own defaults
    EXPECT_EQ(fromSchema.width, renderer.width);
    EXPECT_EQ(fromSchema.height, renderer.height);
    EXPECT_EQ(fromSchema.spp, renderer.spp);
    EXPECT_EQ(fromSchema.seed, renderer.seed);
    EXPECT_EQ(fromSchema.sampler, renderer.sampler);
    EXPECT_EQ(fromSchema.threads, renderer.threads);
    EXPECT_EQ(fromSchema.trace.maxDepth, renderer.trace.maxDepth);
    EXPECT_EQ(fromSchema.trace.nextEvent, renderer.trace.nextEvent);
    EXPECT_EQ(fromSchema.trace.firstHitSplit, renderer.trace.firstHitSplit);
    EXPECT_EQ(fromSchema.trace.firstBounceStream, renderer.trace.firstBounceStream);
    EXPECT_EQ(fromSchema.trace.jointFirstBounce, renderer.trace.jointFirstBounce);
    const StudyConfig study = toStudyConfig(StudyOptions{}, true);
    const StudyConfig own;
    EXPECT_EQ(study.estimators, own.estimators);
    EXPECT_EQ(study.samplers, own.samplers);
    EXPECT_EQ(study.spps, own.spps);
    EXPECT_EQ(study.splitEstimators, own.splitEstimators);
    EXPECT_EQ(study.plots, own.plots);
    ASSERT_EQ(study.modes.size(), 1u);
    EXPECT_EQ(study.modes[0], own.modes[0]);
}

TEST(Schema, SplittingAutoIsEarsWhereARenderCanLearnElseNone) {
    RenderOptions o;  // the command's defaults: 64 spp, no --split, no --joint-first-bounce
    EXPECT_EQ(o.splitting, kAutoSplitting);
    EXPECT_EQ(effectiveSplitting(o), SplittingMode::Ears);
    EXPECT_EQ(renderSettings(o).trace.splitting, SplittingMode::Ears);
    EXPECT_EQ(RenderSettings{}.trace.splitting, SplittingMode::None) << "a bare RenderSettings (tests, benches, the study) does not learn";
    RenderOptions split = o;
    split.split = 2;  // the user chose the first hit's splitting
    EXPECT_EQ(effectiveSplitting(split), SplittingMode::None);
    EXPECT_NO_THROW(checkRenderOptions(split)) << "auto never resolves to a refused pair";
    RenderOptions joint = o;
    joint.jointFirstBounce = true;
    EXPECT_EQ(effectiveSplitting(joint), SplittingMode::None);
    EXPECT_NO_THROW(checkRenderOptions(joint));
    RenderOptions few = o;
    few.spp = kAutoSplittingMinSpp - 1;  // too few samples for learning to pay
    EXPECT_EQ(effectiveSplitting(few), SplittingMode::None);
    few.spp = kAutoSplittingMinSpp;
    EXPECT_EQ(effectiveSplitting(few), SplittingMode::Ears);
    // A name given is the name used, whatever the other settings.
    for (const std::string& name : splittingNames()) {
        RenderOptions given = few;
        given.splitting = name;
        given.estimator = "phong";
        EXPECT_EQ(effectiveSplitting(given), splittingMode(name)) << name;
        resolveSplitting(given);
        EXPECT_EQ(given.splitting, name);
    }
    resolveSplitting(split);
    EXPECT_EQ(split.splitting, "none");
    resolveSplitting(o);
    EXPECT_EQ(o.splitting, "ears");
    resolveSplitting(o);  // idempotent
    EXPECT_EQ(o.splitting, "ears");
}

TEST(Schema, JsonRoundTripAndErrorsNameTheKey) {
    RenderOptions o;
    o.spp = 17, o.width = 33, o.seed = 1ull << 60, o.sampler = "stratified", o.noNee = true;
    o.estimatorOptions.symmetricMode = SymmetricMode::Spread, o.estimatorOptions.symmetricOrbit = 8;
    const nlohmann::json j = schema::toJson(o, renderSchema());
    EXPECT_EQ(j["spp"], 17);
    EXPECT_EQ(j["symmetric_mode"], "spread");
    EXPECT_EQ(j["seed"].get<std::uint64_t>(), 1ull << 60);
    EXPECT_FALSE(j.contains("output")) << "the output path is the command line's, not a setting";
    RenderOptions back;
    schema::fromJson(j, back, renderSchema());
    EXPECT_EQ(schema::toJson(back, renderSchema()), j);
    const auto error = [](const nlohmann::json& bad) {
        RenderOptions r;
        try {
            schema::fromJson(bad, r, renderSchema());
        } catch (const std::invalid_argument& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    EXPECT_EQ(error({{"sp", 4}}), "unknown setting 'sp'");
    EXPECT_EQ(error({{"spp", 0}}), "spp: out of range (got 0)");
    EXPECT_EQ(error({{"spp", 2.5}}), "spp: expected a number (got 2.5)");
    EXPECT_EQ(error({{"symmetric_orbit", 3}}), "symmetric_orbit: not allowed (got 3)");
    EXPECT_EQ(error({{"symmetric_mode", "sideways"}}), "symmetric_mode: unknown symmetric mode 'sideways' (valid: branch, spread)");
    EXPECT_EQ(error({{"sampler", "halton"}}).rfind("unknown sampler 'halton'", 0), 0u);
    EXPECT_EQ(error({{"seed", -1}}), "seed: out of range (got -1)");
}

TEST(Schema, CommandLineOptionsParseAndCheckAsTheSchemaSays) {
    CLI::App app;
    RenderOptions o;
    addSchemaOptions(&app, o, renderSchema());
    std::vector<std::string> args{"--spp",  "12",        "-W",          "7",         "--no-nee", "--symmetric-mode",
                                  "spread", "--sampler", "independent", "scene.json"};
    std::reverse(args.begin(), args.end());  // CLI11 takes a vector in reverse order
    app.parse(args);
    EXPECT_EQ(o.spp, 12u);
    EXPECT_EQ(o.width, 7);
    EXPECT_TRUE(o.noNee);
    EXPECT_FALSE(renderSettings(o).trace.nextEvent);
    EXPECT_EQ(o.estimatorOptions.symmetricMode, SymmetricMode::Spread);
    EXPECT_EQ(o.sampler, "independent");
    EXPECT_EQ(o.scene, "scene.json");
    for (const std::vector<std::string>& bad : {std::vector<std::string>{"--spp", "0"},
                                                {"--symmetric-orbit", "3"},
                                                {"--sampler", "halton"},
                                                {"--symmetric-mode", "x"},
                                                {"--exposure", "-1"}}) {
        CLI::App again;
        RenderOptions r;
        addSchemaOptions(&again, r, renderSchema());
        std::vector<std::string> args(bad.rbegin(), bad.rend());
        EXPECT_THROW(again.parse(args), CLI::ParseError) << bad[0];
    }
}

TEST(Schema, AStudysSettingsInResultsJsonGiveItsConfigurationBack) {
    StudyConfig c;
    c.scene = "scenes/cornell-glossy-100.json";
    c.estimators = {"phong", "symmetric-mix"};
    c.samplers = {"sobol", "independent"};
    c.modes = {SymmetricMode::Branch, SymmetricMode::Spread};
    c.spps = {2, 8};
    c.splits = {2};
    c.budgetPairs = 3;
    c.repeats = 5;
    c.width = 40;
    c.referenceSpp = 512;
    c.options.symmetricOrbit = 4;
    c.plots = false;
    const nlohmann::json j = studySettingsJson(c);
    StudyOptions o;
    schema::fromJson(j, o, studySchema());
    const StudyConfig back = toStudyConfig(o, true);
    EXPECT_EQ(back.scene, c.scene);
    EXPECT_EQ(back.estimators, c.estimators);
    EXPECT_EQ(back.samplers, c.samplers);
    EXPECT_EQ(back.modes, c.modes);
    EXPECT_EQ(back.spps, c.spps);
    EXPECT_EQ(back.splits, c.splits);
    EXPECT_EQ(back.budgetPairs, c.budgetPairs);
    EXPECT_EQ(back.repeats, c.repeats);
    EXPECT_EQ(back.width, c.width);
    EXPECT_EQ(back.referenceSpp, c.referenceSpp);
    EXPECT_EQ(back.options.symmetricOrbit, 4);
    EXPECT_FALSE(back.plots);
}

// report.md's "Command:" (schema::commandLine through studyCommandLine): read back as a shell would split
// it and parsed by the study's own command line, it gives every setting of the study (results.json's
// settings, compared whole), including those the report used to leave out (--splittings, --max-repeats,
// --seed, --reference-spp) and a directory a shell must be given in quotes.
TEST(Schema, AStudysCommandLineInItsReportGivesItsSettingsBack) {
    const auto shellWords = [](const std::string& line) {
        std::vector<std::string> words;
        std::string word;
        bool quoted = false, any = false;
        for (std::size_t i = 0; i < line.size(); ++i) {
            const char ch = line[i];
            if (ch == '\'') {
                quoted = !quoted, any = true;
            } else if (!quoted && ch == '\\' && i + 1 < line.size()) {
                word += line[++i], any = true;
            } else if (!quoted && ch == ' ') {
                if (any) words.push_back(word);
                word.clear(), any = false;
            } else {
                word += ch, any = true;
            }
        }
        if (any) words.push_back(word);
        return words;
    };
    StudyConfig c;
    c.scene = "scenes/cornell-glossy-100.json";
    c.estimators = {"phong"};
    c.spps = {16, 64};
    c.splitEstimators = {"phong"};
    c.splittings = {"none", "ears", "ears-orbit"};
    c.repeats = 6;
    c.targetInterval = 0.1;
    c.maxRepeats = 30;
    c.timeLimit = 40;
    c.width = 128, c.height = 96;
    c.seed = 7;
    c.referenceSpp = 1024;
    c.outDir = "/tmp/it's a study";
    c.plots = false;
    const std::string line = studyCommandLine(c);
    for (const char* flag : {"--splittings none,ears,ears-orbit", "--max-repeats 30", "--seed 7", "--reference-spp 1024", "--no-plots"})
        EXPECT_NE(line.find(flag), std::string::npos) << flag << " missing from: " << line;
    std::vector<std::string> args = shellWords(line);
    std::reverse(args.begin(), args.end());  // CLI11 takes a vector in reverse order
    CLI::App app;
    StudyOptions o;
    addSchemaOptions(&app, o, studySchema());
    app.parse(args);
    const StudyConfig back = toStudyConfig(o, true);
    EXPECT_EQ(back.outDir, c.outDir);
    EXPECT_EQ(studySettingsJson(back), studySettingsJson(c)) << line;
    // The defaults give the scene, the lists and the size alone.
    EXPECT_EQ(studyCommandLine(StudyConfig{}),
              " cornell --estimators cosine,stratified,phong,symmetric,symmetric-shifted,paper --samplers sobol --symmetric-modes branch "
              "--spp 1,4,16,64 --repeats 4 --width 128 --height 128");
}

TEST(Schema, ASceneFilesRenderSettingsApplyUnderTheUsersOwn) {
    const auto dir = std::filesystem::temp_directory_path() / ("symphong-schema-scene-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    const std::string path = (dir / "s.json").string();
    {
        std::ofstream f(path);
        f << R"({"builtin": "cornell", "render": {"spp": 5, "width": 20, "max_depth": 2, "symmetric_mode": "spread", "no_nee": true}})";
    }
    const Scene scene = loadScene(path);
    RenderOptions o;
    o.width = 33;  // given by the user: the scene's 20 must not replace it
    applySceneSettings(o, scene, path, {"width"});
    EXPECT_EQ(o.spp, 5u);
    EXPECT_EQ(o.width, 33);
    EXPECT_EQ(o.maxDepth, 2);
    EXPECT_TRUE(o.noNee);
    EXPECT_EQ(o.estimatorOptions.symmetricMode, SymmetricMode::Spread);
    EXPECT_EQ(o.height, RenderOptions{}.height) << "what neither gives keeps its default";
    {
        std::ofstream f(path);
        f << R"({"builtin": "cornell", "render": {"spp": 0}})";
    }
    RenderOptions r;
    try {
        applySceneSettings(r, loadScene(path), path, {});
        FAIL() << "spp 0 accepted";
    } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()), path + ": \"render\": spp: out of range (got 0)");
    }
    {
        std::ofstream f(path);
        f << R"({"builtin": "cornell", "render": [4]})";
    }
    EXPECT_THROW(loadScene(path), InputError);
    std::filesystem::remove_all(dir);
}

// What every front end calls once the scene is loaded: `auto` is resolved from the settings the scene file
// adds, not from the options before it (a scene's own 16 spp or "split": 2 rule EARS out), a name the user
// gave stays, and a pair the checks refuse is refused whether it came from the scene or the user.
TEST(Schema, FinishRenderOptionsResolvesAutoAfterTheScenesOwnSettings) {
    const auto dir = std::filesystem::temp_directory_path() / ("symphong-schema-finish-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    const std::string path = (dir / "s.json").string();
    const auto finished = [&](const std::string& render, RenderOptions o, const std::set<std::string>& given) {
        {
            std::ofstream f(path);
            f << R"({"builtin": "cornell", "render": )" << render << "}";
        }
        finishRenderOptions(o, loadScene(path), path, given);
        return o;
    };
    EXPECT_EQ(finished(R"({"width": 20})", RenderOptions{}, {}).splitting, "ears") << "64 spp by default: learns";
    EXPECT_EQ(finished(R"({"spp": 16})", RenderOptions{}, {}).splitting, "none") << "the scene's 16 spp are too few";
    EXPECT_EQ(finished(R"({"split": 2})", RenderOptions{}, {}).splitting, "none") << "the scene chose the first hit's split";
    RenderOptions many;
    many.spp = 128;  // the user's spp rule over the scene's 16
    EXPECT_EQ(finished(R"({"spp": 16})", many, {"spp"}).splitting, "ears");
    RenderOptions named;
    named.splitting = "none";
    EXPECT_EQ(finished(R"({"width": 20})", named, {"splitting"}).splitting, "none");
    RenderOptions ears;
    ears.splitting = "ears";
    try {
        finished(R"({"split": 2})", ears, {"splitting"});
        FAIL() << "the scene's split 2 beside the user's ears accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("--split 2 and --splitting ears"), std::string::npos) << e.what();
    }
    std::filesystem::remove_all(dir);
}
