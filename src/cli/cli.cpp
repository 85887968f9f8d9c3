#include "cli/cli.h"

#include "cli/commands.h"
#include "cli/schema_cli.h"
#include "distrib/mpi_job.h"
#include "io/input_error.h"

#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include <cstdio>

namespace symphong {

int runCli(int argc, const char* const* argv) {
    const MpiJob single(nullptr, nullptr);
    return runCli(argc, argv, single);
}

int runCli(int argc, const char* const* argv, const MpiJob& job) {
    if (!job.root()) std::freopen("/dev/null", "w", stdout);  // help and summaries come from rank 0
    CLI::App app{"symphong: a Phong path tracer built to compare Monte Carlo estimators, symmetric sampling among them."};
    app.require_subcommand(1);
    app.set_version_flag("--version", versionText(), "print the version and the libraries it was built with, and exit");
    RenderOptions renderOptions;
    const CLI::App* renderCommand = addRenderCommand(app, renderOptions);
    FurnaceOptions furnaceOptions;
    addFurnaceCommand(app, furnaceOptions);
    StudyOptions studyOptions;
    addStudyCommand(app, studyOptions);
    CompareOptions compareOptions;
    addCompareCommand(app, compareOptions);
    std::string infoScene = "cornell";
    addInfoCommand(app, infoScene);
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        // One line: the problem, then where to read about the command that was being parsed.
        std::string what = e.what();
        for (std::size_t p = what.find('\n'); p != std::string::npos; p = what.find('\n', p)) what.replace(p, 1, "; ");
        std::string command = "symphong";
        for (const CLI::App* sub : app.get_subcommands()) command += " " + sub->get_name();
        if (job.root()) fmt::print(stderr, "symphong: error: {} (see '{} --help')\n", what, command);
        return kBadInput;
    }
    try {
        if (app.got_subcommand("render")) return runRender(renderOptions, givenKeys(renderCommand, renderSchema()), job);
        if (app.got_subcommand("study")) return runStudyCommand(studyOptions, job);
        if (app.got_subcommand("info")) return job.root() ? runInfo(infoScene) : 0;
        // The furnace and compare are not shared among ranks (they take seconds): rank 0 runs them alone.
        if (!job.root()) return 0;
        if (job.size() > 1)
            fmt::print(stderr, "symphong: warning: '{}' does not share its work among MPI ranks; rank 0 runs it alone\n",
                       app.get_subcommands().front()->get_name());
        if (app.got_subcommand("furnace")) return runFurnaceCommand(furnaceOptions);
        if (app.got_subcommand("compare")) return runCompareCommand(compareOptions);
    } catch (const InputError& e) {
        // Errors that reach here are the same on every rank (or were agreed on): reported once.
        if (job.root()) fmt::print(stderr, "symphong: error: {}\n", e.what());
        return kBadInput;
    } catch (const std::exception& e) {
        fmt::print(stderr, "symphong: internal error{}: {}\n", job.size() > 1 ? fmt::format(" on rank {}", job.rank()) : "", e.what());
        if (job.size() > 1) job.abort(1);  // the other ranks may be waiting for this one
        return 1;
    }
    return 0;
}

}  // namespace symphong
