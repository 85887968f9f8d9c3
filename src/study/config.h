// study/config.h — what `symphong study` and `symphong furnace` (and the Python module's study() and
// furnace()) are asked for, described once by their schemas (util/schema.h): each field's name, flag,
// default, range and help. Lists of names are kept as the text the user gave ("a,b" or "all") and turned
// into the configuration by toStudyConfig / toFurnaceTable.
#pragma once

#include "study/furnace.h"
#include "study/study.h"
#include "util/schema.h"

#include <string>
#include <vector>

namespace symphong {

struct StudyOptions {
    StudyConfig config;  ///< the options bind to its fields; the lists below fill the rest
    std::string estimators = "cosine,stratified,phong,symmetric,symmetric-shifted,paper";
    std::string samplers = std::string(kDefaultSampler);
    std::string modes = "branch";
    std::vector<std::uint32_t> spps = {1, 4, 16, 64};
    std::string splitEstimators = "phong,symmetric-mix";
    std::string splittings = "none";
    bool noPlots = false;
    bool noPage = false;
};

struct FurnaceOptions {
    FurnaceTable table;  ///< the options bind to its fields; the lists and --grid fill the rest
    std::string estimators = "all";
    std::string environments = "constant";
    bool grid = false;
    std::string json;
};

/// Every field of StudyOptions, in the order `symphong study --help` lists them.
const schema::Schema<StudyOptions>& studySchema();
/// Every field of FurnaceOptions, in the order `symphong furnace --help` lists them.
const schema::Schema<FurnaceOptions>& furnaceSchema();

/// A list of names: "all" (every name), or names separated by commas. With `validate`, a name not in
/// `all` is an InputError "WHAT: unknown name 'x' (valid: ..., or all)"; without, the names are taken as
/// they are (the configuration's own checks name them later).
std::vector<std::string> nameList(const std::string& text, const std::vector<std::string>& all, const char* what, bool validate);

/// The study's configuration: the lists parsed (names checked when `validateNames`), plots unless
/// --no-plots.
StudyConfig toStudyConfig(const StudyOptions& o, bool validateNames);
/// The options that give this configuration (the lists joined with commas, plots as --no-plots).
StudyOptions studyOptionsOf(const StudyConfig& c);
/// The arguments of `symphong study` that give this configuration (report.md's "Command:"): the scene, the
/// lists and the size, then every other option that is not its default, as studySchema() names them.
std::string studyCommandLine(const StudyConfig& c);
/// The configuration's settings as JSON through studySchema() (results.json's "settings": fromJson of
/// it into StudyOptions and toStudyConfig give the configuration back).
nlohmann::json studySettingsJson(const StudyConfig& c);
/// The settings that can change the study's rows (all but threads, --out, the plots and --resume): what
/// a resumed study must share with the results it keeps.
nlohmann::json studyResultSettingsJson(const StudyConfig& c);

/// The furnace's table: the lists parsed, --grid's exponents and angles.
FurnaceTable toFurnaceTable(const FurnaceOptions& o, bool validateNames);

}  // namespace symphong
