#include "thread_clock.h"

#include <chrono>

#include <tbb/parallel_invoke.h>

namespace foton {

namespace {

uint64_t steady_ns() {
    return uint64_t(std::chrono::duration_cast<std::chrono::nanoseconds>(
                        std::chrono::steady_clock::now().time_since_epoch())
                        .count());
}

std::atomic<ThreadClock::Source> g_source{steady_ns};
thread_local ThreadClock* t_innermost = nullptr;

uint64_t now() {
    return g_source.load(std::memory_order_relaxed)();
}

}  // namespace

ThreadClock::ThreadClock(BusyTime* sink) : sink_(sink) {
    if (!sink_) return;
    const uint64_t t = now();
    outer_ = t_innermost;
    if (outer_) outer_->sink_->nanoseconds.fetch_add(t - outer_->since_, std::memory_order_relaxed);
    t_innermost = this;
    since_ = t;
}

ThreadClock::~ThreadClock() {
    if (!sink_) return;
    const uint64_t t = now();
    sink_->nanoseconds.fetch_add(t - since_, std::memory_order_relaxed);
    t_innermost = outer_;
    if (outer_) outer_->since_ = t;
}

BusyTime* ThreadClock::current() {
    return t_innermost ? t_innermost->sink_ : nullptr;
}

BusyTime* ThreadClock::for_chunks() {
    BusyTime* b = current();
    if (b) b->chunks_timed = true;
    return b;
}

void ThreadClock::set_source(Source s) {
    g_source = s ? s : steady_ns;
}

std::function<void(const std::function<void()>&, const std::function<void()>&)>
timed_parallel_invoke(BusyTime* busy) {
    return [busy](const std::function<void()>& a, const std::function<void()>& b) {
        tbb::parallel_invoke(
            [&] {
                const ThreadClock clock(busy);
                a();
            },
            [&] {
                const ThreadClock clock(busy);
                b();
            });
    };
}

}  // namespace foton
