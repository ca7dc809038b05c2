#pragma once
// Thread pinning for scaling studies (`foton scale --pin`). While pinning is on, every thread
// that enters a PinnedArena runs on one CPU: the thread in arena slot i on
// cpu_topology().cpu_order[i] (physical cores first, socket by socket), and it gets its own
// affinity back when it leaves. Off by default: the operating system places the threads.
#include <vector>

#include <tbb/task_arena.h>
#include <tbb/task_scheduler_observer.h>

namespace foton {

// Process-wide, like OMP_PROC_BIND: set before rendering.
void set_thread_pinning(bool on);
bool thread_pinning();

class ArenaPinning : public tbb::task_scheduler_observer {
  public:
    explicit ArenaPinning(tbb::task_arena& arena);
    ~ArenaPinning() override;
    ArenaPinning(const ArenaPinning&) = delete;
    ArenaPinning& operator=(const ArenaPinning&) = delete;

    void on_scheduler_entry(bool worker) override;
    void on_scheduler_exit(bool worker) override;

  private:
    std::vector<int> order_;
};

// A task arena whose threads are pinned while pinning is on: what every render's and build's
// arena is, so that no stage escapes --pin.
class PinnedArena : public tbb::task_arena {
  public:
    explicit PinnedArena(int threads) : tbb::task_arena(threads), pinning_(*this) {}

  private:
    ArenaPinning pinning_;
};

}  // namespace foton
