#include "render/progress.h"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>

namespace symphong {

bool stderrIsTerminal() { return ::isatty(STDERR_FILENO) == 1; }

ProgressBar::ProgressBar(const std::atomic<std::uint64_t>& counter, std::uint64_t total, std::string unit, bool enabled)
    : done_([&counter] { return static_cast<double>(counter.load(std::memory_order_relaxed)); }),
      total_(static_cast<double>(total)),
      unit_(std::move(unit)),
      enabled_(enabled) {
    start();
}

ProgressBar::ProgressBar(std::function<double()> done, double total, std::function<std::string()> label, bool enabled)
    : done_(std::move(done)), total_(total), label_(std::move(label)), enabled_(enabled) {
    start();
}

void ProgressBar::start() {
    if (!enabled_) return;
    thread_ = std::thread([this] {
        const auto start = std::chrono::steady_clock::now();
        while (!stop_.load()) {
            draw(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), false);
            for (int i = 0; i < 20 && !stop_.load(); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
        }
        draw(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), true);
    });
}

ProgressBar::~ProgressBar() { finish(); }

void ProgressBar::finish() {
    if (!thread_.joinable()) return;
    stop_.store(true);
    thread_.join();
}

std::string ProgressBar::formatDuration(double s) {
    if (s >= 3600) return fmt::format("{}h{:02}m", static_cast<int>(s / 3600), static_cast<int>(s / 60) % 60);
    if (s >= 60) return fmt::format("{}m{:02}s", static_cast<int>(s / 60), static_cast<int>(s) % 60);
    return fmt::format("{:.1f}s", s);
}

std::string ProgressBar::formatCount(double v) {
    if (v >= 1e9) return fmt::format("{:.2f} G", v / 1e9);
    if (v >= 1e6) return fmt::format("{:.2f} M", v / 1e6);
    if (v >= 1e3) return fmt::format("{:.1f} k", v / 1e3);
    return fmt::format("{:.0f} ", v);
}

void ProgressBar::draw(double elapsed, bool last) const {
    const double done = std::clamp(done_(), 0.0, total_);
    const double frac = total_ > 0 ? done / total_ : 1.0;
    constexpr int kWidth = 30;
    const int filled = static_cast<int>(frac * kWidth);
    std::string bar(static_cast<std::size_t>(filled), '#');
    bar.resize(kWidth, '.');
    const double rate = elapsed > 0 ? done / elapsed : 0.0;
    const std::string eta = (done > 0 && done < total_) ? formatDuration(elapsed * (1.0 - frac) / frac) : "--";
    const std::string tail = label_ ? label_() : formatCount(rate) + unit_ + "/s";
    fmt::print(stderr, "\r[{}] {:5.1f}%  elapsed {}  ETA {}  {}   ", bar, 100.0 * frac, formatDuration(elapsed), eta, tail);
    if (last) fmt::print(stderr, "\n");
    std::fflush(stderr);
}

}  // namespace symphong
