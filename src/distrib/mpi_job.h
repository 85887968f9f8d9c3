// distrib/ — running one job across processes with MPI (Open MPI from Debian), on one machine or many:
// the job's ranks (this file), and the work shared among them: one render (render.h), one study
// (study.h). A process not started by mpirun/mpiexec/srun never initialises MPI and runs exactly as a
// plain program. Only the program links this layer; the Python module stays a single process.
#pragma once

#include <string>

namespace symphong {

class MpiJob {
public:
    /// Initialises MPI (with thread support for the tile dispatcher) when the process was started by an
    /// MPI launcher; otherwise a job of one rank that makes no MPI call.
    MpiJob(int* argc, char*** argv);
    ~MpiJob();  ///< finalises MPI
    MpiJob(const MpiJob&) = delete;
    MpiJob& operator=(const MpiJob&) = delete;

    /// Whether the launcher's environment is present (Open MPI, PMIx, PMI).
    static bool launchedByMpi();

    bool active() const { return active_; }  ///< MPI initialised (even with one rank)
    int rank() const { return rank_; }
    int size() const { return size_; }
    bool root() const { return rank_ == 0; }

    /// Collective: every rank passes its error ("" when it has none). Returns "" on every rank when no
    /// rank failed; otherwise, on every rank, the error of the lowest failing rank, prefixed with
    /// "rank N: " unless that is rank 0. Lets all ranks stop together after a failure that only some of
    /// them saw (a file missing on one node) and report it once, from rank 0.
    std::string firstError(const std::string& localError) const;

    /// Ends every rank of the job at once (after an error that the others cannot learn of).
    [[noreturn]] void abort(int code) const;

private:
    bool active_ = false;
    int rank_ = 0, size_ = 1;
};

/// The MPI library in use (its own first words, e.g. "Open MPI v4.1.4").
std::string mpiVersion();

}  // namespace symphong
