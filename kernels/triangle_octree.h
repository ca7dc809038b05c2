#pragma once
// Octree over a triangle mesh (the ray-tracing thesis' chapter 8, beside the uniform grid and
// the BVH): each inner node splits its box at the centre into eight children; a triangle is
// referenced by every child it meets (separating-axis test); a node stays a leaf when it holds few
// triangles, at the depth limit, or when splitting would copy its triangles into too many
// children. Leaves hold their triangles in SoA blocks for the SIMD Möller–Trumbore kernel (as
// the grid's cells do). Rays walk the children front to back by the parametric algorithm of
// Revelles, Ureña and Lastra (2000): from the ray's entry and mid-plane parameters alone, with
// no box tests, and stop at the first leaf whose exit lies beyond the closest hit so far.
#include <cstdint>
#include <vector>

#include "huge_page_allocator.h"
#include "moller_trumbore.h"
#include "ray1.h"
#include "tree_counters.h"
#include "triangle_block.h"

namespace foton::kern {

struct OctreeParams {
    uint32_t leaf_triangles = 2 * kBlockWidth;  // a node with no more stays a leaf
    int max_depth = 12;
    // A split whose children would reference more than this many times the node's triangles
    // is not made (triangles larger than the children would be copied into most of them).
    float max_duplication = 3.f;
};

class TriangleOctree {
  public:
    // positions: xyz per vertex; indices: three per triangle; hit ids are triangle indices.
    void build(const float* positions, const uint32_t* indices, std::size_t num_triangles,
               const OctreeParams& params = {});
    // Closest hit with r.tmin < t < min(r.tmax, hit.t); updates `hit`.
    bool intersect(const Ray1& r, TriHit& hit, TreeCounters* counters = nullptr) const;
    // Any hit with r.tmin < t < r.tmax.
    bool occluded(const Ray1& r, TreeCounters* counters = nullptr) const;

    std::size_t num_nodes() const { return nodes_.size(); }
    std::size_t num_references() const { return references_; }
    int depth() const { return depth_; }
    std::size_t memory_bytes() const;
    bool empty() const { return blocks_.empty(); }

  private:
    // Inner node: its eight children are nodes [first, first + 8), child c holding the upper
    // half along x if c & 4, along y if c & 2, along z if c & 1. Leaf: blocks
    // [first, first + blocks).
    struct Node {
        uint32_t first = 0;
        uint32_t blocks = 0;
        bool leaf = true;
    };
    // A ray moves along an axis when its direction component is at least this.
    static constexpr float kNoDirection = 1e-20f;
    // What a walk keeps for the whole ray: its origin (mirrored), which axes it moves along,
    // which it was mirrored in (child c of the walk is child c ^ mirror), where it starts.
    struct Walk {
        float o[3] = {0, 0, 0};
        bool moves[3] = {true, true, true};
        uint32_t mirror = 0;
        float tmin = 0.f;
    };

    void build_node(uint32_t node, const float lo[3], const float hi[3],
                    std::vector<uint32_t>& tris, int depth);
    // Walks the subtree of `node` (box [lo, hi] in the walk's mirrored space) over the ray
    // parameters [t0, t1] of its box per axis, calling leaf(first block, blocks, t_exit) for
    // each non-empty leaf in order until it returns true; cull() bounds the parameters still
    // worth entering.
    template <class Leaf, class Cull>
    bool walk(uint32_t node, const float t0[3], const float t1[3], const float lo[3],
              const float hi[3], const Walk& w, Cull&& cull, Leaf&& leaf, uint64_t& visited) const;
    template <class Leaf, class Cull>
    bool traverse(const Ray1& r, Cull&& cull, Leaf&& leaf, uint64_t& visited) const;

    const float* positions_ = nullptr;
    const uint32_t* indices_ = nullptr;
    OctreeParams params_;
    float lo_[3] = {0, 0, 0}, hi_[3] = {0, 0, 0};
    std::vector<Node> nodes_;
    std::vector<TriangleBlock, HugePageAllocator<TriangleBlock>> blocks_;
    std::size_t references_ = 0;
    int depth_ = 0;
};

}  // namespace foton::kern
