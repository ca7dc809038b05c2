#pragma once
// The irradiance cache's octree (the lecture notes' structure): every record is stored in
// each node, at one level, that its sphere of influence overlaps; the level is the deepest
// whose node edge still spans the sphere's diameter, so large spheres sit high in the tree
// and small ones low, and a sphere overlaps at most two nodes per axis there. A point query
// walks from the root to the deepest node containing the point and collects the records of
// every node on the way: a record whose sphere contains the point overlaps the node of its
// level that contains the point, so it is among them (and only once).
//
// Insertion is incremental; queries are read-only and may run in parallel with each other
// (never with an insertion: the cache is frozen while a pass reads it).
#include <array>
#include <cstdint>
#include <vector>

#include "engine/core/math.h"

namespace foton {

class RecordOctree {
  public:
    static constexpr int kMaxDepth = 20;

    // An empty tree over the cube that contains `bounds` (slightly enlarged).
    void reset(const Bounds3& bounds);
    // Adds item `index`, a sphere of radius r around c.
    void insert(uint32_t index, const Vec3& c, float r);
    // Calls f(index) for the items of every node from the root to p's deepest node.
    template <class F>
    void for_each_candidate(const Vec3& p, F&& f) const {
        if (nodes_.empty()) return;
        int ix, iy, iz;
        cell(p, kMaxDepth, ix, iy, iz);
        int32_t node = 0;
        for (int depth = 0;; ++depth) {
            for (uint32_t i : nodes_[std::size_t(node)].items) f(i);
            if (depth == kMaxDepth) return;
            const int shift = kMaxDepth - depth - 1;
            const int child =
                ((ix >> shift) & 1) | (((iy >> shift) & 1) << 1) | (((iz >> shift) & 1) << 2);
            node = nodes_[std::size_t(node)].child[std::size_t(child)];
            if (node < 0) return;
        }
    }

  private:
    struct Node {
        std::array<int32_t, 8> child;
        std::vector<uint32_t> items;
        Node() { child.fill(-1); }
    };
    // Integer cell of p at `depth` (clamped to the root cube).
    void cell(const Vec3& p, int depth, int& ix, int& iy, int& iz) const;

    std::vector<Node> nodes_;
    Vec3 lo_{0.f, 0.f, 0.f};
    float size_ = 1.f;
};

}  // namespace foton
