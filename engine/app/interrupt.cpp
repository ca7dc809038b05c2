#include "interrupt.h"

#include <unistd.h>
#include <csignal>
#include <cstring>

#include "engine/film/image_io.h"

namespace foton::app {

namespace {

std::atomic<bool> g_requested{false};
struct sigaction g_old_int, g_old_term;

extern "C" void on_signal(int) {
    if (!g_requested.exchange(true)) {
        static const char msg[] =
            "\nfoton: interrupted: finishing the pass in flight and writing the image (again to "
            "quit at once)\n";
        [[maybe_unused]] const ssize_t n = write(STDERR_FILENO, msg, sizeof msg - 1);
        return;
    }
    remove_pending_temp_file();
    _exit(kExitInterrupted);
}

}  // namespace

InterruptGuard::InterruptGuard() {
    static_assert(std::atomic<bool>::is_always_lock_free, "a signal handler sets it");
    g_requested = false;
    struct sigaction sa;
    std::memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, &g_old_int);
    sigaction(SIGTERM, &sa, &g_old_term);
}

InterruptGuard::~InterruptGuard() {
    sigaction(SIGINT, &g_old_int, nullptr);
    sigaction(SIGTERM, &g_old_term, nullptr);
}

const std::atomic<bool>& InterruptGuard::requested() {
    return g_requested;
}

}  // namespace foton::app
