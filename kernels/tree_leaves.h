#pragma once
// The closest-hit and any-hit queries of a spatial subdivision whose leaves are triangle
// blocks (the octree, the kd-tree), written once: a tree supplies only its walk, which calls
// leaf(first block, blocks, t at the leaf's exit) for each leaf in front-to-back order until
// that returns true, and skips ranges starting beyond cull().
#include "tree_counters.h"
#include "triangle_bvh.h"

namespace foton::kern {

// Closest hit with r.tmin < t < min(r.tmax, hit.t); ties to the smaller id, as brute force and
// the BVH. Past a hit, ranges entered up to t * kBvhCullScale are still walked: a triangle hit
// at the same t (a shared edge on a splitting plane) in the next leaf may have the smaller id.
template <class Walk>
bool closest_in_leaves(const Ray1& r, const TriangleBlock* blocks, TriHit& hit,
                       TreeCounters* counters, Walk&& walk) {
    if (r.tmax < hit.t) hit.t = r.tmax;
    const bvh_detail::LeafRay<kBlockWidth> lr(r);
    bool found = false;
    uint64_t visited = 0, tests = 0;
    walk([&] { return hit.valid() ? hit.t * kBvhCullScale : hit.t; },
         [&](uint32_t first, uint32_t count, float exit) {
             found |= bvh_detail::leaf_closest(lr, blocks + first, count, hit);
             tests += count;
             // A hit well inside this leaf's range cannot be beaten (or tied) by a later leaf.
             return found && hit.t * kBvhCullScale < exit;
         },
         visited);
    if (counters) counters->nodes += visited, counters->blocks += tests;
    return found;
}

// Any hit with r.tmin < t < r.tmax.
template <class Walk>
bool any_in_leaves(const Ray1& r, const TriangleBlock* blocks, TreeCounters* counters,
                   Walk&& walk) {
    uint64_t visited = 0, tests = 0;
    const bool hit = walk([&] { return r.tmax; },
                          [&](uint32_t first, uint32_t count, float) {
                              for (uint32_t b = first; b < first + count; ++b) {
                                  ++tests;
                                  if (occluded_block(r, blocks[b])) return true;
                              }
                              return false;
                          },
                          visited);
    if (counters) counters->nodes += visited, counters->blocks += tests;
    return hit;
}

}  // namespace foton::kern
