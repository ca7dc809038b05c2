#pragma once
// A wide SAH BVH over curve segments (kernels/curve_intersect.h), each split into 2^split
// parts first (pbrt-v4's splitdepth, 3 by default: a part's box is far tighter around a thin
// curve than the whole segment's), the parts stored in leaf order beside it: what the engine's
// CurveIntersector traces and what bench/bench_curves measures against Embree's curves. The
// binary build is collapsed into nodes of N = simd::kHalfWidth children, one SIMD test for
// their boxes, walked front to back as the triangle BVH is (bvh_box_ray.h); a leaf's parts
// are tested one by one by the scalar curve kernel. Its reference is the loop over every part
// (tests/test_curves.cpp).
#include <cstdint>
#include <vector>

#include "bvh_build.h"
#include "bvh_node.h"
#include "curve_intersect.h"
#include "huge_page_allocator.h"
#include "simd.h"

namespace foton::kern {

class CurveBvh {
  public:
    CurveBvh() = default;
    // ribbon[i]: segment i keeps its normals' orientation (else it faces the ray).
    CurveBvh(const std::vector<CurveSegment>& segments, const std::vector<uint8_t>& ribbon,
             const BvhBuildParams::ParallelInvoke& parallel = {}, int split = 3);
    // The closest hit within [tmin, min(tmax, hit.t)]: true, `hit` (u along the whole segment)
    // and the segment's index in the build's list in `id`. `tests` counts part tests.
    bool closest(const Ray1& ray, CurveHit& hit, uint32_t& id, uint64_t& tests) const;
    bool any(const Ray1& ray, uint64_t& tests) const;
    // The closest hits of n rays (ray i's hit.t on entry bounds it, as closest()'s): the same
    // hits as closest() one by one, their walks interleaved a step of each in turn, so that one
    // ray's loads are under way while the others work (incoherent rays wait on memory, not on
    // the tests). found[i] says whether ray i hit; ids[i] as closest()'s id.
    void closest_stream(const Ray1* rays, std::size_t n, CurveHit* hits, uint32_t* ids,
                        uint8_t* found, uint64_t& tests) const;
    std::size_t memory_bytes() const;
    bool empty() const { return parts_.empty(); }

    static constexpr std::size_t kWidth = simd::kHalfWidth;
    using Node = WideNode<kWidth>;

  private:
    template <class Leaf>
    void walk(const Ray1& ray, const float& tcull, Leaf&& leaf) const;
    // The loads of the children in `mask` of `node`, started (nodes or leaf parts).
    void prefetch_children(const Node& node, uint32_t mask) const;
    // Ray `part`'s closest-hit test against leaf part i: true when closer (hit updated).
    bool test_part(const CurveRay& cr, uint32_t i, CurveHit& hit) const {
        const Part& q = parts_[i];
        return intersect_curve(cr, q.segment(normals_), q.ribbon != 0, hit);
    }

    std::vector<Node, HugePageAllocator<Node>> nodes_;
    uint32_t root_ = kBvhEmpty;  // a node, or the one leaf of a tiny tree
    // A part as a leaf reads it: one cache line (incoherent rays are bound by the loads of
    // nodes and parts, not by the tests), a ribbon's normals kept apart.
    struct alignas(64) Part {
        float cp[4][3];
        float w0, w1;
        uint32_t ribbon;  // keeps its normals' orientation (else it faces the ray)
        uint32_t index;   // into normals_, ids_ and u0_
        CurveSegment segment(const std::vector<float>& normals) const;
    };
    std::vector<Part, HugePageAllocator<Part>> parts_;  // in leaf order
    std::vector<float> normals_;                        // n0, n1 of every part (6 floats)
    std::vector<uint32_t> ids_;                         // leaf order -> the build's index
    std::vector<float> u0_;                             // where a part starts in its segment's u
    float part_du_ = 1.f;                               // every part spans 1 / 2^split of it
};

}  // namespace foton::kern
