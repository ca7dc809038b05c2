#include "progress_line.h"

#include <algorithm>
#include <chrono>
#include <cstdio>

namespace foton::app {

ProgressLine::ProgressLine(Progress& progress) : progress_(progress) {
    progress_.on_change([this] {
        // A new task on show is drawn at once, by the thread that began it: a phase of a few
        // milliseconds is seen too. Changes within the same task wait for the drawing thread.
        std::lock_guard lock(mutex_);
        const std::optional<Progress::View> v = progress_.view();
        if (v && v->name != shown_) {
            draw(*v);
            last_ = std::chrono::steady_clock::now();
        } else {
            changed_ = true;
            wake_.notify_one();
        }
    });
    thread_ = std::thread([this] { run(); });
}

ProgressLine::~ProgressLine() {
    progress_.on_change(nullptr);
    {
        std::lock_guard lock(mutex_);
        stop_ = true;
    }
    wake_.notify_one();
    thread_.join();
    if (drawn_ > 0) std::fprintf(stderr, "\r%*s\r", int(drawn_), "");
    std::fflush(stderr);
}

std::string ProgressLine::format(const Progress::View& v) {
    constexpr int kBar = 20;
    std::string name = v.name.substr(0, 22);
    if (v.others > 0) name = name.substr(0, 19) + " +" + std::to_string(std::min(v.others, 9));
    char bar[kBar + 1];
    const int fill = v.fraction >= 0.0 ? int(v.fraction * kBar) : 0;
    for (int i = 0; i < kBar; ++i) bar[i] = i < fill ? '#' : '.';
    bar[kBar] = 0;
    char line[160];
    if (v.fraction < 0.0)
        std::snprintf(line, sizeof line, "%-22s [%s]    ...  %7.1f s", name.c_str(), bar,
                      std::min(v.elapsed, 99999.0));
    else if (v.eta < 0.0)
        std::snprintf(line, sizeof line, "%-22s [%s] %5.1f%%  %7.1f s", name.c_str(), bar,
                      100.0 * v.fraction, std::min(v.elapsed, 99999.0));
    else
        std::snprintf(line, sizeof line, "%-22s [%s] %5.1f%%  %7.1f s  ETA %7.1f s", name.c_str(),
                      bar, 100.0 * v.fraction, std::min(v.elapsed, 99999.0),
                      std::min(v.eta, 99999.0));
    return line;
}

void ProgressLine::draw(const Progress::View& v) {
    const std::string line = format(v);
    shown_ = v.name;
    // Pad over a longer line drawn before, so nothing of it is left.
    const int pad = int(drawn_ > line.size() ? drawn_ - line.size() : 0);
    std::fprintf(stderr, "\r%s%*s", line.c_str(), pad, "");
    std::fflush(stderr);
    drawn_ = std::max(drawn_, line.size());
}

void ProgressLine::run() {
    using namespace std::chrono;
    std::unique_lock lock(mutex_);
    while (!stop_) {
        // Wait for a change, or 200 ms for the numbers to move.
        wake_.wait_for(lock, milliseconds(200), [this] { return stop_ || changed_; });
        if (stop_) break;
        const auto now = steady_clock::now();
        if (now - last_ < milliseconds(50)) {
            // Drawn just now: let changes gather for the rest of the 50 ms.
            wake_.wait_for(lock, milliseconds(50) - (now - last_), [this] { return stop_; });
            if (stop_) break;
        }
        changed_ = false;
        if (const std::optional<Progress::View> v = progress_.view()) draw(*v);
        last_ = steady_clock::now();
    }
}

}  // namespace foton::app
