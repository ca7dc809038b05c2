#include "stage_graph.h"

#include <algorithm>
#include <memory>

#include <tbb/flow_graph.h>

namespace foton {

uint32_t StageGraph::add(const std::string& name, Body body) {
    Node& n = nodes_.emplace_back();
    n.name = name;
    n.body = std::move(body);
    return uint32_t(nodes_.size() - 1);
}

uint32_t StageGraph::declare(const std::string& name) {
    return add(name, nullptr);
}

void StageGraph::edge(uint32_t from, uint32_t to) {
    const std::pair<uint32_t, uint32_t> e{from, to};
    if (std::find(edges_.begin(), edges_.end(), e) == edges_.end()) edges_.push_back(e);
}

void StageGraph::record(uint32_t node, double seconds, uint64_t items) {
    Node& n = nodes_[node];
    n.nanoseconds.fetch_add(uint64_t(seconds * 1e9), std::memory_order_relaxed);
    n.items.fetch_add(items, std::memory_order_relaxed);
    n.runs.fetch_add(1, std::memory_order_relaxed);
}

void StageGraph::run(tbb::task_arena& arena) {
    std::vector<uint32_t> all;
    for (uint32_t i = 0; i < nodes_.size(); ++i)
        if (nodes_[i].body) all.push_back(i);
    run(arena, all);
}

void StageGraph::run(tbb::task_arena& arena, const std::vector<uint32_t>& which) {
    using Msg = tbb::flow::continue_msg;
    arena.execute([&] {
        tbb::flow::graph g;
        tbb::flow::broadcast_node<Msg> start(g);
        std::vector<std::unique_ptr<tbb::flow::continue_node<Msg>>> flow(nodes_.size());
        for (const uint32_t i : which) {
            if (!nodes_[i].body) continue;
            flow[i] = std::make_unique<tbb::flow::continue_node<Msg>>(g, [this, i](const Msg&) {
                const ProgressTask task(progress_, nodes_[i].name, 0);
                NodeTimer timer(*this, i);
                const ThreadClock clock(&nodes_[i].busy);
                timer.items = nodes_[i].body();
            });
        }
        std::vector<uint8_t> has_pred(nodes_.size(), 0);
        for (const auto& [from, to] : edges_) {
            if (!flow[from] || !flow[to]) continue;
            tbb::flow::make_edge(*flow[from], *flow[to]);
            has_pred[to] = 1;
        }
        for (uint32_t i = 0; i < nodes_.size(); ++i)
            if (flow[i] && !has_pred[i]) tbb::flow::make_edge(start, *flow[i]);
        start.try_put(Msg());
        g.wait_for_all();
    });
}

std::vector<uint32_t> StageGraph::sinks() const {
    std::vector<uint32_t> out;
    for (uint32_t i = 0; i < nodes_.size(); ++i) {
        bool has_succ = false;
        for (const auto& e : edges_) has_succ |= e.first == i;
        if (!has_succ) out.push_back(i);
    }
    return out;
}

GraphStats StageGraph::report() const {
    GraphStats r;
    for (const Node& n : nodes_) {
        const bool chunks_timed = n.body && n.busy.chunks_timed.load();
        const double seconds =
            chunks_timed ? n.busy.seconds() : double(n.nanoseconds.load()) * 1e-9;
        r.nodes.push_back(
            {n.name, seconds, n.items.load(), n.runs.load(), !n.body || chunks_timed});
    }
    r.edges = edges_;
    return r;
}

}  // namespace foton
