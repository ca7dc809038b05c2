#include "progress_bar.h"

#include <algorithm>
#include <chrono>
#include <cstdio>

namespace foton {

ProgressBar::ProgressBar(const std::atomic<std::size_t>& done, std::size_t total)
    : done_(done), total_(total), thread_([this] { run(); }) {}

ProgressBar::~ProgressBar() {
    stop_ = true;
    thread_.join();
    // Blank exactly what was drawn (the line grows with the times shown), then return.
    if (drawn_ > 0) std::fprintf(stderr, "\r%*s\r", drawn_, "");
    std::fflush(stderr);
}

void ProgressBar::run() {
    const auto start = std::chrono::steady_clock::now();
    while (!stop_) {
        std::this_thread::sleep_for(std::chrono::milliseconds(200));
        const std::size_t d = done_.load(std::memory_order_relaxed);
        const double frac = total_ ? std::min(1.0, double(d) / double(total_)) : 1.0;
        const double el =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        const double eta = frac > 0 ? el * (1.0 - frac) / frac : 0.0;
        char bar[31];
        const int fill = int(frac * 30);
        for (int i = 0; i < 30; ++i) bar[i] = i < fill ? '#' : '.';
        bar[30] = 0;
        const int n =
            std::fprintf(stderr, "\r[%s] %5.1f%%  %6.1fs  ETA %6.1fs", bar, 100 * frac, el, eta);
        drawn_ = std::max(drawn_, n - 1);  // without the carriage return
        std::fflush(stderr);
    }
}

}  // namespace foton
