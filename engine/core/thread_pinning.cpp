#include "thread_pinning.h"

#include <pthread.h>
#include <sched.h>

#include <atomic>

#include "engine/core/cpu_topology.h"

namespace foton {

namespace {
std::atomic<bool> g_pinning{false};

// The affinity a thread had before it entered a pinned arena (restored when it leaves).
thread_local cpu_set_t t_saved;
thread_local int t_depth = 0;
}  // namespace

void set_thread_pinning(bool on) {
    g_pinning = on;
}
bool thread_pinning() {
    return g_pinning;
}

ArenaPinning::ArenaPinning(tbb::task_arena& arena) : tbb::task_scheduler_observer(arena) {
    if (!g_pinning) return;
    order_ = cpu_topology().cpu_order;
    if (!order_.empty()) observe(true);
}

ArenaPinning::~ArenaPinning() {
    if (is_observing()) observe(false);
}

void ArenaPinning::on_scheduler_entry(bool) {
    const int slot = tbb::this_task_arena::current_thread_index();
    if (slot < 0) return;
    if (t_depth++ == 0) pthread_getaffinity_np(pthread_self(), sizeof t_saved, &t_saved);
    cpu_set_t one;
    CPU_ZERO(&one);
    CPU_SET(order_[std::size_t(slot) % order_.size()], &one);
    pthread_setaffinity_np(pthread_self(), sizeof one, &one);
}

void ArenaPinning::on_scheduler_exit(bool) {
    if (t_depth == 0) return;
    if (--t_depth == 0) pthread_setaffinity_np(pthread_self(), sizeof t_saved, &t_saved);
}

}  // namespace foton
