#pragma once
// Curves for every backend (layered_intersector.h): a binary BVH over the scene's curve
// segments (kernels/curve_intersect.h) above the backend, so the curve kernel can also be
// measured on its own.
#include <memory>

#include "kernels/curve_bvh.h"
#include "layered_intersector.h"

namespace foton {

class CurveIntersector final : public LayeredIntersector<CurveIntersector> {
  public:
    CurveIntersector(const Scene& scene, std::unique_ptr<Intersector> inner);
    std::size_t memory_bytes() const override;

  private:
    friend class LayeredIntersector<CurveIntersector>;
    // The curve segments alone (no backend): the closest curve hit closer than hit.t.
    bool closest_own(const kern::Ray1& ray, Hit1& hit, TraceCounters& c) const;
    bool any_own(const kern::Ray1& ray, TraceCounters& c) const;

    struct SegmentRef {
        uint32_t geom, segment;
    };
    std::vector<SegmentRef> refs_;  // the BVH's segment ids -> their object and index
    kern::CurveBvh bvh_;
};

}  // namespace foton
