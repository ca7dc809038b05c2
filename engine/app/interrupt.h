#pragma once
// Ctrl-C and kill during a render: the first SIGINT or SIGTERM asks the render to stop after
// the pass in flight (camera renders stop handing out tiles at once), and the image so far is
// written with its true sample count; a second one ends the process at once, removing the
// temporary file of an image being written. Either way the exit code is kExitInterrupted.
#include <atomic>

namespace foton::app {

inline constexpr int kExitInterrupted = 130;  // 128 + SIGINT, as shells report it

// Installs the handlers for its lifetime.
class InterruptGuard {
  public:
    InterruptGuard();
    ~InterruptGuard();
    InterruptGuard(const InterruptGuard&) = delete;
    InterruptGuard& operator=(const InterruptGuard&) = delete;
    // Set by the first signal; the render's RenderOptions::cancel.
    static const std::atomic<bool>& requested();
};

}  // namespace foton::app
