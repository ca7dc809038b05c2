#pragma once
// The progress line on a terminal: the current task of a Progress (its name, a bar, the
// percentage, its elapsed time and ETA), redrawn in place on stderr at most 20 times a
// second and whenever a task begins or ends, from a thread of its own. Destroying it
// blanks exactly what it drew.
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <string>
#include <thread>

#include "engine/core/progress.h"

namespace foton::app {

class ProgressLine {
  public:
    explicit ProgressLine(Progress& progress);
    ~ProgressLine();
    ProgressLine(const ProgressLine&) = delete;
    ProgressLine& operator=(const ProgressLine&) = delete;

    // The text of one line for `v` (no carriage return), at most 79 characters.
    static std::string format(const Progress::View& v);

  private:
    void run();
    void draw(const Progress::View& v);  // with mutex_ held
    Progress& progress_;
    std::mutex mutex_;
    std::condition_variable wake_;
    bool stop_ = false, changed_ = false;
    std::size_t drawn_ = 0;                       // the length of the line on screen
    std::string shown_;                           // the task drawn last
    std::chrono::steady_clock::time_point last_;  // when
    std::thread thread_;
};

}  // namespace foton::app
