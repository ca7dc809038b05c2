#pragma once
// Binned SAH construction of a binary BVH over axis-aligned primitive boxes, and its collapse
// into a wide (N-ary) tree. Generic: the caller supplies one box per primitive (triangles,
// spheres, anything) and packs the leaves itself (bvh_triangles.h does SIMD triangle blocks).
//
// Build (after Wald 2007, "On fast construction of SAH-based BVHs"): top down; at each node the
// primitives' centroids are sorted into `bins` equal bins along each axis, the SAH cost of every
// plane between bins is swept from both sides, and the cheapest plane splits the node. A leaf's
// cost counts SIMD blocks, ceil(n / leaf_block), not primitives: a leaf of 4 costs as much as a
// leaf of 1 when 4 triangles take one test. Subtrees are built in parallel through the injected
// `parallel_invoke` (kernels do not depend on TBB), and the result does not depend on it: each
// subtree owns a fixed range of node slots, so the tree is the same for any thread count.
//
// Collapse (after Wald, Benthin, Boulos 2008): a wide node takes a binary node's two children
// and keeps opening the child with the largest surface area until it has N children, so one
// SIMD box test serves N children.
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "bvh_node.h"
#include "ray1.h"

namespace foton::kern {

// One primitive as the builder sees it: its box and the caller's id. 32 bytes, two 16-byte
// halves the binning loads as SIMD registers.
struct alignas(16) PrimRef {
    float lo[3];
    uint32_t id;
    float hi[3];
    uint32_t pad;
};

struct BvhBuildParams {
    uint32_t bins = 32;
    uint32_t max_leaf = 8;    // primitives per leaf at most
    uint32_t leaf_block = 4;  // primitives one SIMD leaf test takes (the SAH's unit; a power of 2)
    float traversal_cost = 1.f;      // one binary node visit, in leaf-block tests
    uint32_t parallel_grain = 4096;  // subtrees smaller than this are built by the calling thread
    // Runs two jobs, possibly in parallel (the engine passes tbb::parallel_invoke); empty: one
    // after the other.
    using ParallelInvoke =
        std::function<void(const std::function<void()>&, const std::function<void()>&)>;
    ParallelInvoke parallel;
};

// Binary tree, node 0 the root. An inner node has count == 0 and two children; a leaf covers
// prims[first .. first + count) of BinaryBvh::prims.
struct BinaryNode {
    float lo[3], hi[3];
    uint32_t left, right;   // inner nodes
    uint32_t first, count;  // leaves
    bool leaf() const { return count != 0; }
};

struct BinaryBvh {
    // Room for the worst case, 2n - 1 nodes, allocated without initialisation; the nodes used
    // (`used`, about n / 2) are packed at the front, so the pages behind them are never
    // touched (first touches of fresh pages were a third of the build time).
    std::unique_ptr<BinaryNode[]> nodes;
    std::size_t used = 0;
    std::vector<uint32_t> prims;  // caller ids in leaf order
    uint32_t depth = 0;
    bool empty() const { return prims.empty(); }
};

// Builds over `refs` (reordered in place). Primitives with an empty or non-finite box must not
// be passed: the caller skips them (bad geometry builds a valid tree without it).
BinaryBvh build_binary_bvh(std::vector<PrimRef>& refs, const BvhBuildParams& params);

// Walks a binary tree in front-to-back child order, visiting the primitives of every leaf
// whose box the ray enters before bound() (read at every node, so a closer hit found by
// visit prunes the rest) until visit(primitive id) returns true.
template <class Bound, class Visit>
void walk_binary_bvh(const BinaryBvh& bvh, const Ray1& ray, Bound&& bound, Visit&& visit) {
    if (bvh.empty()) return;
    const float o[3] = {ray.ox, ray.oy, ray.oz};
    const float inv[3] = {1.f / ray.dx, 1.f / ray.dy, 1.f / ray.dz};
    uint32_t stack[128];
    std::size_t sp = 0;
    stack[sp++] = 0;
    while (sp) {
        const BinaryNode& n = bvh.nodes[stack[--sp]];
        float tnear;
        if (!slab_test_scalar(n.lo, n.hi, o, inv, ray.tmin, bound(), tnear)) continue;
        if (!n.leaf()) {
            stack[sp++] = n.right;
            stack[sp++] = n.left;
            continue;
        }
        for (uint32_t i = n.first; i < n.first + n.count; ++i)
            if (visit(bvh.prims[i])) return;
    }
}

// SAH cost of a binary tree: sum over nodes of area(node) / area(root) times the traversal cost
// (inner) or the primitives (leaves); the number researchers compare builders by.
double sah_cost(const BinaryBvh& bvh, float traversal_cost = 1.f, float primitive_cost = 1.f);

// A wide tree before its leaves are packed: node i has up to `width` children, each an inner
// node (index) or a leaf (a BinaryNode leaf's range), with their boxes.
struct WideChild {
    float lo[3], hi[3];
    bool leaf = false;
    uint32_t index = 0;  // wide node (inner) or first prim (leaf)
    uint32_t count = 0;  // prims of a leaf
};
struct WideTree {
    uint32_t width = 0;
    std::vector<std::vector<WideChild>> nodes;  // nodes[0] is the root; depth-first order
    uint32_t depth = 0;
};

// Collapses `bvh` into nodes of at most `width` children. A tree whose root is a leaf becomes
// one wide node with that single leaf child.
WideTree collapse_bvh(const BinaryBvh& bvh, uint32_t width);

// SAH cost of a wide tree with the same constants (a wide node counts once per visit).
double sah_cost(const WideTree& tree, float traversal_cost = 1.f, float primitive_cost = 1.f);

}  // namespace foton::kern
