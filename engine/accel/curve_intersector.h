#pragma once
// Curves for every backend: a wrapper that asks the backend for its closest hit and then its
// own binary BVH over the scene's curve segments (kernels/curve_intersect.h) for a closer one.
// The backends never see curves (they skip ObjectKind::Curves), so every backend, thread count
// and rank finds the same curve hits, and the curve kernel can be measured on its own.
#include <memory>

#include "intersector.h"
#include "kernels/curve_bvh.h"

namespace foton {

class CurveIntersector final : public Intersector {
  public:
    CurveIntersector(const Scene& scene, std::unique_ptr<Intersector> inner);
    const char* name() const override { return inner_->name(); }
    void intersect(const RayBatch& rays, HitBatch& hits, TraceCounters& c) const override;
    void occluded(const RayBatch& rays, std::vector<uint8_t>& occluded,
                  TraceCounters& c) const override;
    bool intersect1(const kern::Ray1& ray, Hit1& hit, TraceCounters& c) const override;
    bool occluded1(const kern::Ray1& ray, TraceCounters& c) const override;
    std::size_t memory_bytes() const override;

  private:
    // The curve segments alone (no backend): the closest curve hit closer than hit.t.
    bool closest_curve(const kern::Ray1& ray, Hit1& hit, TraceCounters& c) const;
    bool any_curve(const kern::Ray1& ray, TraceCounters& c) const;

    struct SegmentRef {
        uint32_t geom, segment;
    };
    const Scene& scene_;
    std::unique_ptr<Intersector> inner_;
    std::vector<SegmentRef> refs_;  // the BVH's segment ids -> their object and index
    kern::CurveBvh bvh_;
};

}  // namespace foton
