// render/progress.h — a progress bar on stderr (only when stderr is a terminal) that polls a counter
// from its own thread: percentage, elapsed time, ETA and rate.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <thread>

namespace symphong {

class ProgressBar {
public:
    /// Starts drawing when `enabled`; `unit` names what the counter counts ("samples").
    ProgressBar(const std::atomic<std::uint64_t>& counter, std::uint64_t total, std::string unit, bool enabled);
    /// A bar over any measure of work: `done()` out of `total`, with `label()` shown after the bar
    /// instead of a rate.
    ProgressBar(std::function<double()> done, double total, std::function<std::string()> label, bool enabled);
    ~ProgressBar();
    /// Draws the final state and stops the thread.
    void finish();

    /// "1h02m", "3m05s", "12.3s".
    static std::string formatDuration(double seconds);
    /// "12.3 M", "456 k", "12".
    static std::string formatCount(double value);

private:
    void draw(double elapsed, bool last) const;

    void start();

    std::function<double()> done_;
    double total_;
    std::string unit_;
    std::function<std::string()> label_;
    bool enabled_;
    std::atomic<bool> stop_{false};
    std::thread thread_;
};

/// Whether stderr is a terminal.
bool stderrIsTerminal();

}  // namespace symphong
