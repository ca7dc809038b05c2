// Exclusive thread time (core/thread_clock.h) and the stage graph's use of it: a clock stops
// while a later clock runs on its thread, so nested and stolen work is charged once, to its
// own stage; pass nodes that time their chunks report thread time, the others wall time.
#include <catch2/catch.hpp>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "engine/core/thread_clock.h"
#include "engine/transport/run/stage_graph.h"

using namespace foton;

namespace {

// A clock the test moves by hand (one thread).
uint64_t g_now = 0;
uint64_t manual_now() {
    return g_now;
}

struct ManualClock {
    ManualClock() { ThreadClock::set_source(manual_now); }
    ~ManualClock() { ThreadClock::set_source(nullptr); }
};

}  // namespace

TEST_CASE("thread clocks charge their time exclusively, innermost first", "[thread_clock][fast]") {
    const ManualClock manual;
    BusyTime outer, inner, other;
    g_now = 100;
    {
        const ThreadClock a(&outer);
        CHECK(ThreadClock::current() == &outer);
        g_now = 103;
        {
            const ThreadClock b(&inner);  // a chunk nested in the outer one: the outer stops
            CHECK(ThreadClock::current() == &inner);
            g_now = 105;
            {
                const ThreadClock c(&other);  // another stage's chunk picked up meanwhile
                g_now = 111;
            }
            g_now = 112;
            {
                const ThreadClock same(&inner);  // nested in its own stage: charged once
                g_now = 114;
            }
        }
        CHECK(ThreadClock::current() == &outer);
        g_now = 120;
        const ThreadClock untimed(nullptr);  // does nothing
        CHECK(ThreadClock::current() == &outer);
        g_now = 121;
    }
    CHECK(ThreadClock::current() == nullptr);
    CHECK(outer.nanoseconds == 3 + 7);      // 100-103 and 114-121
    CHECK(inner.nanoseconds == 2 + 1 + 2);  // 103-105, 111-112, 112-114
    CHECK(other.nanoseconds == 6);          // 105-111
    CHECK(outer.nanoseconds + inner.nanoseconds + other.nanoseconds == 121 - 100);
}

TEST_CASE("pass nodes that time their chunks report thread time, the others wall time",
          "[thread_clock][fast]") {
    StageGraph graph;
    auto chunks = [] {
        BusyTime* busy = ThreadClock::for_chunks();
        tbb::parallel_for(tbb::blocked_range<int>(0, 64, 1), [&](const tbb::blocked_range<int>&) {
            const ThreadClock clock(busy);
            volatile double x = 0.0;
            for (int i = 0; i < 20000; ++i) x = x + 1.0;
        });
        return uint64_t(64);
    };
    const uint32_t a = graph.add("a", chunks);
    const uint32_t b = graph.add("b", chunks);  // beside a
    const uint32_t c = graph.add("c", [] { return uint64_t(1); });
    graph.edge(a, c);
    graph.edge(b, c);
    tbb::task_arena arena(2);
    graph.run(arena);
    graph.run(arena);
    const GraphStats st = graph.report();
    REQUIRE(st.nodes.size() == 3);
    for (const uint32_t n : {a, b}) {
        CHECK(st.nodes[n].thread_time);
        CHECK(st.nodes[n].runs == 2);
        CHECK(st.nodes[n].items == 128);
        CHECK(st.nodes[n].busy_seconds > 0.0);
    }
    CHECK_FALSE(st.nodes[c].thread_time);
    CHECK(ThreadClock::current() == nullptr);
}
