#pragma once
// SAH kd-tree over a triangle mesh (the ray-tracing thesis' chapter 8, beside the grid, the
// octree and the BVH), built in O(n log n) by Wald and Havran's algorithm (2006): the
// candidate planes of every axis are kept as one sorted list of triangle events (start, end,
// lying in the plane) that each node sweeps once for the cheapest plane by the surface area
// heuristic, and splits in order for its children, so nothing is sorted again below the root
// but the few triangles the plane cuts. Those are clipped to each child's box ("perfect
// splits"): a child's candidate planes are where its part of the triangle starts and ends,
// not where the whole triangle's box does.
//
// Leaves hold their triangles in SoA blocks for the SIMD Möller–Trumbore kernel (as the grid's
// cells and the octree's leaves do). Rays walk the tree front to back with a stack of the far
// children (the recursive ray traversal of Havran's thesis, iterative), and stop at the first
// leaf whose exit lies beyond the closest hit so far.
#include <bit>
#include <cstdint>
#include <functional>
#include <vector>

#include "huge_page_allocator.h"
#include "moller_trumbore.h"
#include "ray1.h"
#include "tree_counters.h"
#include "triangle_block.h"

namespace foton::kern {

struct KdTreeParams {
    // The SAH's costs: stepping through one inner node, and testing one triangle (in units
    // of the former). A triangle costs less than a node step here: leaves are tested W
    // triangles at a time. These and the leaf size were chosen on the kernel benchmark's
    // bunny and dragon diffuse and shadow rays (docs/results.md).
    float traversal_cost = 1.f;
    float intersection_cost = 0.5f;
    // The cost of a split with an empty side is scaled by this (Wald and Havran's lambda):
    // cutting off empty space is cheap to walk and pays off more than the SAH counts.
    float empty_bonus = 0.8f;
    uint32_t leaf_triangles = 2 * kBlockWidth;  // a node with no more stays a leaf
    int max_depth = 0;  // 0: 8 + 1.3 log2(n) (pbrt's rule), at most kMaxDepth
    static constexpr int kMaxDepth = 60;
    // Runs two jobs, possibly in parallel (the engine passes tbb::parallel_invoke; kernels do
    // not depend on TBB); empty: one after the other. The upper levels' two subtrees are built
    // as separate fragments either way and joined in order, so the tree is the same.
    using ParallelInvoke =
        std::function<void(const std::function<void()>&, const std::function<void()>&)>;
    ParallelInvoke parallel;
    int parallel_depth = 4;           // nodes above this depth split their work in two
    uint32_t parallel_grain = 16384;  // and only with at least this many triangles
};

class TriangleKdTree {
  public:
    // positions: xyz per vertex; indices: three per triangle; hit ids are triangle indices.
    void build(const float* positions, const uint32_t* indices, std::size_t num_triangles,
               const KdTreeParams& params = {});
    // Closest hit with r.tmin < t < min(r.tmax, hit.t); updates `hit`.
    bool intersect(const Ray1& r, TriHit& hit, TreeCounters* counters = nullptr) const;
    // Any hit with r.tmin < t < r.tmax.
    bool occluded(const Ray1& r, TreeCounters* counters = nullptr) const;

    std::size_t num_nodes() const { return nodes_.size(); }
    std::size_t num_leaves() const { return leaves_; }
    std::size_t num_references() const { return references_; }
    int depth() const { return depth_; }
    // The SAH cost of the tree (traversal and intersection costs weighted by the root-relative
    // surface area of each node), the figure the build minimises greedily.
    double sah_cost() const { return sah_; }
    std::size_t memory_bytes() const;
    bool empty() const { return blocks_.empty(); }

    // Eight bytes. Inner: the split position and its axis (0-2), the lower child next in the
    // array and the upper one at `index`. Leaf (axis 3): triangle blocks [index, index + count).
    struct Node {
        uint32_t word;  // inner: the split's bits; leaf: the number of blocks
        uint32_t bits;  // axis in the low two bits, index above them

        float split() const { return std::bit_cast<float>(word); }
        uint32_t count() const { return word; }
        bool leaf() const { return (bits & 3u) == 3u; }
        int axis() const { return int(bits & 3u); }
        uint32_t index() const { return bits >> 2; }
    };

  private:
    static constexpr float kNoDirection = 1e-30f;
    template <class Leaf, class Cull>
    bool traverse(const Ray1& r, Cull&& cull, Leaf&& leaf, uint64_t& visited) const;

    const float* positions_ = nullptr;
    const uint32_t* indices_ = nullptr;
    float lo_[3] = {0, 0, 0}, hi_[3] = {0, 0, 0};
    std::vector<Node> nodes_;
    std::vector<TriangleBlock, HugePageAllocator<TriangleBlock>> blocks_;
    std::size_t references_ = 0, leaves_ = 0;
    int depth_ = 0;
    double sah_ = 0.0;

    friend class KdTreeBuilder;
};

}  // namespace foton::kern
