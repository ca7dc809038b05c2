#pragma once
// A progress bar with ETA on stderr, drawn from its own thread until destroyed.
#include <atomic>
#include <cstddef>
#include <thread>

namespace foton {

class ProgressBar {
  public:
    // Draws `done` out of `total` every 200 ms.
    ProgressBar(const std::atomic<std::size_t>& done, std::size_t total);
    ~ProgressBar();
    ProgressBar(const ProgressBar&) = delete;
    ProgressBar& operator=(const ProgressBar&) = delete;

  private:
    void run();
    const std::atomic<std::size_t>& done_;
    std::size_t total_;
    std::atomic<bool> stop_{false};
    int drawn_ = 0;  // the longest line drawn, in characters
    std::thread thread_;
};

}  // namespace foton
