#pragma once
// Curves for every backend (layered_intersector.h): a wide BVH over the scene's curve
// segments (kernels/curve_bvh.h) above the backend, so the curve kernel can also be measured
// on its own. A batch's rays walk it as one stream (CurveBvh::closest_stream, the same hits
// as one by one).
#include <memory>

#include "kernels/curve_bvh.h"
#include "layered_intersector.h"

namespace foton {

class CurveIntersector final : public LayeredIntersector<CurveIntersector> {
  public:
    CurveIntersector(const Scene& scene, std::unique_ptr<Intersector> inner);
    std::size_t memory_bytes() const override;
    void intersect(const RayBatch& rays, HitBatch& hits, TraceCounters& c) const override;

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
    // A batch's rays and curve hits (per thread: intersect is const and called concurrently).
    struct Stream {
        std::vector<kern::Ray1> rays;
        std::vector<kern::CurveHit> hits;
        std::vector<uint32_t> ids;
        std::vector<uint8_t> found;
    };
};

}  // namespace foton
