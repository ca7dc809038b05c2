#pragma once
// Exclusive thread time, for stages that share the threads (the stage graph's passes that
// run side by side: SPPM's visible points beside its photons, the global and caustic photon
// passes and their balancing). Such a stage's wall time times the threads says nothing about
// what it used; its thread time does.
//
// A ThreadClock charges the time it runs on its thread to a BusyTime, and stops while a
// clock started later on the same thread runs: a worker that waits inside one stage's chunk
// (nested parallelism) and picks up another stage's chunk meanwhile charges that chunk to its
// own stage, once. A stage's thread time is then its body's own thread (serial work and
// waiting for its loops) plus its chunks, wherever they ran.
#include <atomic>
#include <cstdint>
#include <functional>

namespace foton {

struct BusyTime {
    std::atomic<uint64_t> nanoseconds{0};
    // Handed to parallel chunks (ThreadClock::for_chunks): it holds all the stage's thread
    // time, not only its own thread's.
    std::atomic<bool> chunks_timed{false};
    double seconds() const { return double(nanoseconds.load()) * 1e-9; }
};

class ThreadClock {
  public:
    // Null: does nothing (an untimed caller).
    explicit ThreadClock(BusyTime* sink);
    ~ThreadClock();
    ThreadClock(const ThreadClock&) = delete;
    ThreadClock& operator=(const ThreadClock&) = delete;

    // What the innermost running clock of this thread charges (null: none).
    static BusyTime* current();
    // The same, marked as timing its chunks: a stage's body reads it on its own thread and
    // hands it to the chunks of its parallel loops, each of which runs a ThreadClock on it.
    static BusyTime* for_chunks();

    // The clock's time source, in nanoseconds; tests replace it (null: steady_clock).
    using Source = uint64_t (*)();
    static void set_source(Source s);

  private:
    BusyTime* sink_;
    ThreadClock* outer_ = nullptr;
    uint64_t since_ = 0;  // when it last started or resumed
};

// tbb::parallel_invoke whose two jobs charge `busy` (a graph node body's for_chunks(), or
// null): for a recursive build inside a node that runs beside others, such as a photon map's
// balance. Its type is the kernels' ParallelInvoke (point_kdtree.h, bvh_build.h).
std::function<void(const std::function<void()>&, const std::function<void()>&)>
timed_parallel_invoke(BusyTime* busy);

}  // namespace foton
