// cli/ — the `symphong` command line (CLI11): parses arguments, turns every InputError into a one-line
// message and exit code 2, shows progress, and prints the run's summary; under mpirun, it speaks from
// rank 0 only. It holds no rendering logic.
#pragma once

namespace symphong {

class MpiJob;

/// Runs the command line; returns the process exit code (0 ok, 2 bad input, 1 internal failure).
int runCli(int argc, const char* const* argv);

/// The same as one rank of an MPI job (distrib/): `render` shares its tiles among the ranks and rank 0
/// writes the image; messages and output come from rank 0 only.
int runCli(int argc, const char* const* argv, const MpiJob& job);

}  // namespace symphong
