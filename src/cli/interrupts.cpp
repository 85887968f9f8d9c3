#include "cli/interrupts.h"

#include "distrib/mpi_job.h"

#include <csignal>

#include <unistd.h>

namespace symphong {

std::atomic<bool> gInterrupted{false};
std::atomic<int> gInterruptSignal{0};

namespace {

std::atomic<bool> gRendering{false};
constexpr char kLauncherStopped[] = "symphong: the MPI launcher is stopping the job (Ctrl-C, or a rank ended)\n";

extern "C" void onInterrupt(int signal) {
    int none = 0;
    gInterruptSignal.compare_exchange_strong(none, signal);
    gInterrupted.store(true);
}

extern "C" void onLauncherStopStudy(int) {
    if (!gInterrupted.exchange(true)) [[maybe_unused]]
        const auto n = ::write(STDERR_FILENO, kLauncherStopped, sizeof kLauncherStopped - 1);
}

extern "C" void onLauncherStopRender(int) {
    if (!gRendering.load()) return;  // writing the image: let it finish
    constexpr char tail[] = "symphong: no image was written\n";
    [[maybe_unused]] const auto a = ::write(STDERR_FILENO, kLauncherStopped, sizeof kLauncherStopped - 1);
    [[maybe_unused]] const auto b = ::write(STDERR_FILENO, tail, sizeof tail - 1);
    ::_exit(143);
}

}  // namespace

LauncherStopGuard::LauncherStopGuard(const MpiJob& job, LauncherStop what) {
    const bool shared = job.size() > 1;
    gInterrupted = false;
    gInterruptSignal = 0;
    if (what == LauncherStop::StopRender) {
        if (shared && !job.root()) {  // the other ranks follow rank 0
            install(SIGINT, SIG_IGN), install(SIGTERM, SIG_IGN);
        } else {
            install(SIGINT, onInterrupt), install(SIGTERM, onInterrupt);
        }
    } else if (what == LauncherStop::EndRender) {
        if (!shared || !job.root()) return;
        gRendering = true;
        install(SIGTERM, onLauncherStopRender);
    } else if (!job.root()) {
        install(SIGINT, SIG_IGN), install(SIGTERM, SIG_IGN);
    } else {
        install(SIGINT, onInterrupt), install(SIGTERM, shared ? onLauncherStopStudy : onInterrupt);
    }
}

LauncherStopGuard::~LauncherStopGuard() {
    gRendering = false;
    for (const auto& [signal, handler] : previous_) std::signal(signal, handler);
}

void LauncherStopGuard::install(int signal, void (*handler)(int)) { previous_.emplace_back(signal, std::signal(signal, handler)); }

}  // namespace symphong
