#pragma once
// A binary SAH BVH over curve segments (kernels/curve_intersect.h), each split into 2^split
// parts first (pbrt-v4's splitdepth, 3 by default: a part's box is far tighter around a thin
// curve than the whole segment's), the parts stored in leaf order beside it: what the engine's
// CurveIntersector traces and what bench/bench_curves measures against Embree's curves.
#include <cstdint>
#include <vector>

#include "bvh_build.h"
#include "curve_intersect.h"

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
    std::size_t memory_bytes() const;
    bool empty() const { return segments_.empty(); }

  private:
    BinaryBvh bvh_;                       // prims[i] = i: leaves index the arrays below
    std::vector<CurveSegment> segments_;  // the parts, in leaf order
    std::vector<uint32_t> ids_;           // leaf order -> the build's index
    std::vector<float> u0_;               // where a part starts in its segment's u
    float part_du_ = 1.f;                 // every part spans 1 / 2^split of it
    std::vector<uint8_t> ribbon_;
};

}  // namespace foton::kern
