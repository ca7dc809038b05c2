#pragma once
// Analytic shapes and CSG trees for every backend (layered_intersector.h): a binary BVH over
// the scene's AnalyticShapes, above the backend and the curve wrapper.
#include <memory>

#include "kernels/bvh_build.h"
#include "layered_intersector.h"

namespace foton {

class ShapeIntersector final : public LayeredIntersector<ShapeIntersector> {
  public:
    ShapeIntersector(const Scene& scene, std::unique_ptr<Intersector> inner);
    std::size_t memory_bytes() const override;

  private:
    friend class LayeredIntersector<ShapeIntersector>;
    // The shapes alone: the closest shape hit before hit.t (or ray.tmax on a miss).
    bool closest_own(const kern::Ray1& ray, Hit1& hit, TraceCounters& c) const;
    bool any_own(const kern::Ray1& ray, TraceCounters& c) const;

    const Scene& scene_;
    kern::BinaryBvh bvh_;  // over the shape objects; prims are geometry ids
};

}  // namespace foton
