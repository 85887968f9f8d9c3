// cli/interrupts.h — Ctrl-C and the MPI launcher's signals. Ctrl-C stops a study cleanly (SIGINT): rows
// finished so far are kept. Under mpirun, Ctrl-C reaches the ranks as SIGTERM (mpirun turns its SIGINT
// into SIGTERM to every rank, then SIGKILL a second later), and so does the end of a job one of whose
// ranks died. Rank 0 then says so at once: a render ends (its image is only written after the last
// tile), a study stops as after Ctrl-C; the other ranks ignore the signal and follow rank 0 (or are
// killed by mpirun).
#pragma once

#include <atomic>
#include <utility>
#include <vector>

namespace symphong {

class MpiJob;

/// Set by the handlers when a study or a render in passes should stop.
extern std::atomic<bool> gInterrupted;
/// The signal that set gInterrupted (SIGINT or SIGTERM), 0 before one arrives.
extern std::atomic<int> gInterruptSignal;

/// EndRender: a one-pass render ends at once under the MPI launcher's SIGTERM. StopStudy: a study stops
/// cleanly. StopRender: a render in passes (render/progressive.h) stops after the tiles in flight and
/// keeps what it has (its checkpoint and image), on SIGINT and SIGTERM alike (Slurm sends SIGTERM).
enum class LauncherStop { EndRender, StopStudy, StopRender };

/// Installs the interruption handlers for the scope of a render or a study, and restores the previous
/// ones. Without MPI: a study handles SIGINT and SIGTERM (a batch system's stop) alike; a render keeps
/// the default (the image is written atomically at the end, so nothing is left behind).
class LauncherStopGuard {
public:
    LauncherStopGuard(const MpiJob& job, LauncherStop what);
    ~LauncherStopGuard();
    LauncherStopGuard(const LauncherStopGuard&) = delete;
    LauncherStopGuard& operator=(const LauncherStopGuard&) = delete;

private:
    void install(int signal, void (*handler)(int));
    std::vector<std::pair<int, void (*)(int)>> previous_;
};

}  // namespace symphong
