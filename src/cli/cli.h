// cli/ — the `symphong` command line (CLI11): parses arguments, turns every InputError into a one-line
// message and exit code 2, shows progress, and prints the run's summary. It holds no rendering logic.
#pragma once

namespace symphong {

/// Runs the command line; returns the process exit code (0 ok, 2 bad input, 1 internal failure).
int runCli(int argc, const char* const* argv);

}  // namespace symphong
