// cli/commands.h — the commands of `symphong`, one file each (render_command.cpp, info_command.cpp,
// furnace_command.cpp, study_command.cpp): each adds its subcommand to the application, with its options
// built from its settings schema (cli/schema_cli.h), and runs it. cli.cpp parses and dispatches;
// interrupts.h handles Ctrl-C and the MPI launcher's signals.
#pragma once

#include "compare/compare.h"
#include "render/settings.h"
#include "study/config.h"

#include <CLI/CLI.hpp>

#include <memory>
#include <set>
#include <string>

namespace symphong {

class Estimator;
class MpiJob;
struct Scene;

/// The exit code of bad input (every InputError).
inline constexpr int kBadInput = 2;

/// makeEstimator, its std::invalid_argument as an InputError "--estimator: ...".
std::unique_ptr<Estimator> estimatorOrInputError(const std::string& name, const EstimatorOptions& options);

/// `symphong --version`: the program's version and its libraries' (version.cpp).
std::string versionText();

/// Adds `render`; returns its subcommand (to ask which options were given).
CLI::App* addRenderCommand(CLI::App& app, RenderOptions& o);
/// given: the schema keys of the options on the command line (the scene's "render" settings fill the rest).
int runRender(const RenderOptions& o, const std::set<std::string>& given, const MpiJob& job);

/// InputError unless `path` is an .exr file that can be created (--variance-output).
void checkVarianceOutput(const std::string& path);

/// `symphong render` in passes (RenderOptions::progressive()): stop rules, checkpoints, resume
/// (long_render.cpp). Returns the exit code (128 + the signal when SIGINT or SIGTERM stopped it).
int renderInPasses(const RenderOptions& o, const Scene& scene, const Estimator& estimator, const std::string& output, const MpiJob& job);

void addInfoCommand(CLI::App& app, std::string& scene);
int runInfo(const std::string& spec);

void addFurnaceCommand(CLI::App& app, FurnaceOptions& o);
int runFurnaceCommand(const FurnaceOptions& o);

void addCompareCommand(CLI::App& app, CompareOptions& o);
int runCompareCommand(const CompareOptions& o);

void addStudyCommand(CLI::App& app, StudyOptions& o);
int runStudyCommand(StudyOptions& o, const MpiJob& job);

}  // namespace symphong
