#pragma once
// A render as a graph of named stages. Nodes added with add() run on a oneTBB flow graph:
// each run() starts every node once, after all its predecessors, in parallel where the edges
// allow (the photon passes, the balancing of each map, ...). Nodes declared with declare()
// are run by a tile pipeline of their own (camera_driver.h: tiles stream through camera
// gather, final gather and accumulation) and report to the same graph, after the nodes they
// depend on have finished. Every node's busy time and items go to --stats and --stats-json.
//
// An add()ed node's time is its wall time, unless its parallel loops time their chunks with
// a ThreadClock on ThreadClock::for_chunks() (read in the body, on its thread): then it is the
// node's exact thread time, which nodes that run side by side need (thread_clock.h).
#include <atomic>
#include <cstdint>
#include <deque>
#include <functional>
#include <string>
#include <vector>

#include <tbb/task_arena.h>

#include "engine/core/progress.h"
#include "engine/core/stats.h"
#include "engine/core/thread_clock.h"

namespace foton {

class StageGraph {
  public:
    using Body = std::function<uint64_t()>;  // returns the items it processed

    // A node that runs `body` once per run(), after its predecessors.
    uint32_t add(const std::string& name, Body body);
    // A node run elsewhere (by a pipeline), which reports through record().
    uint32_t declare(const std::string& name);
    // `to` starts after `from` has finished (for add()ed nodes, run() enforces it).
    void edge(uint32_t from, uint32_t to);
    // Thread-safe: `node` was busy `seconds` on one thread and processed `items`.
    void record(uint32_t node, double seconds, uint64_t items);

    // Runs every add()ed node once inside `arena`; returns when all have finished.
    void run(tbb::task_arena& arena);
    // Runs only these add()ed nodes (a pass of one part of the render, such as the cache
    // fill's, in a graph that holds the photon passes too), with the edges among them.
    void run(tbb::task_arena& arena, const std::vector<uint32_t>& nodes);
    // The nodes that nothing added after them depends on yet (where a next stage attaches).
    std::vector<uint32_t> sinks() const;
    GraphStats report() const;
    // Where the nodes report: each run of an add()ed node is a task of its name (of unknown
    // size: nodes that know theirs report a sized task of their own through progress()).
    void set_progress(Progress* p) { progress_ = p; }
    Progress* progress() const { return progress_; }

  private:
    struct Node {
        std::string name;
        Body body;  // empty for declared nodes
        std::atomic<uint64_t> nanoseconds{0}, items{0}, runs{0};
        BusyTime busy;  // the body's thread and its timed chunks
    };
    std::deque<Node> nodes_;  // deque: atomics do not move
    std::vector<std::pair<uint32_t, uint32_t>> edges_;
    Progress* progress_ = nullptr;
};

// Times a node's work on one thread and records it on destruction.
class NodeTimer {
  public:
    NodeTimer(StageGraph& graph, uint32_t node) : graph_(graph), node_(node) {}
    ~NodeTimer() { graph_.record(node_, clock_.lap(), items); }
    NodeTimer(const NodeTimer&) = delete;
    NodeTimer& operator=(const NodeTimer&) = delete;
    uint64_t items = 0;

  private:
    StageGraph& graph_;
    uint32_t node_;
    StageClock clock_;
};

}  // namespace foton
