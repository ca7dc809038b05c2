#pragma once
// Analytic shapes and CSG trees for every backend: a wrapper that asks the backend (and the
// curve wrapper below it) for its closest hit and then its own binary BVH over the scene's
// AnalyticShapes for a closer one. The backends never see these shapes (traced_by_backend),
// so every backend, thread count and rank finds the same shape hits.
#include <memory>

#include "intersector.h"
#include "kernels/bvh_build.h"

namespace foton {

class ShapeIntersector final : public Intersector {
  public:
    ShapeIntersector(const Scene& scene, std::unique_ptr<Intersector> inner);
    const char* name() const override { return inner_->name(); }
    void intersect(const RayBatch& rays, HitBatch& hits, TraceCounters& c) const override;
    void occluded(const RayBatch& rays, std::vector<uint8_t>& occluded,
                  TraceCounters& c) const override;
    bool intersect1(const kern::Ray1& ray, Hit1& hit, TraceCounters& c) const override;
    bool occluded1(const kern::Ray1& ray, TraceCounters& c) const override;
    std::size_t memory_bytes() const override;

  private:
    // The shapes alone: the closest shape hit before hit.t (or ray.tmax on a miss).
    bool closest_shape(const kern::Ray1& ray, Hit1& hit, TraceCounters& c) const;
    bool any_shape(const kern::Ray1& ray, TraceCounters& c) const;

    const Scene& scene_;
    std::unique_ptr<Intersector> inner_;
    kern::BinaryBvh bvh_;  // over the shape objects; prims are geometry ids
};

}  // namespace foton
