#pragma once
// What curves and analytic shapes share: a wrapper that asks the backend below it for its
// closest hit (or occlusion) and then its own primitives for a closer one. Derived supplies
//   bool closest_own(const kern::Ray1&, Hit1& hit, TraceCounters&) const  // closer than hit.t
//   bool any_own(const kern::Ray1&, TraceCounters&) const
// and memory_bytes(); the backends never see those primitives (traced_by_backend), so every
// backend, thread count and rank finds the same hits on them.
#include <memory>

#include "intersector.h"

namespace foton {

template <class Derived>
class LayeredIntersector : public Intersector {
  public:
    explicit LayeredIntersector(std::unique_ptr<Intersector> inner) : inner_(std::move(inner)) {}
    const char* name() const override { return inner_->name(); }

    void intersect(const RayBatch& rays, HitBatch& hits, TraceCounters& c) const override {
        inner_->intersect(rays, hits, c);
        for (std::size_t i = 0; i < rays.size(); ++i) {
            Hit1 h{hits.t[i], hits.u[i], hits.v[i], hits.prim[i], hits.geom[i]};
            if (h.geom == kNoHit) h.t = kInfinity;
            if (self().closest_own(ray_at(rays, i), h, c)) store_hit(hits, i, h);
        }
    }
    void occluded(const RayBatch& rays, std::vector<uint8_t>& occ,
                  TraceCounters& c) const override {
        inner_->occluded(rays, occ, c);
        for (std::size_t i = 0; i < rays.size(); ++i)
            if (!occ[i]) occ[i] = self().any_own(ray_at(rays, i), c) ? 1 : 0;
    }
    bool intersect1(const kern::Ray1& ray, Hit1& hit, TraceCounters& c) const override {
        const bool inner_hit = inner_->intersect1(ray, hit, c);
        if (!inner_hit) hit.t = kInfinity;
        return self().closest_own(ray, hit, c) || inner_hit;
    }
    bool occluded1(const kern::Ray1& ray, TraceCounters& c) const override {
        return inner_->occluded1(ray, c) || self().any_own(ray, c);
    }

  protected:
    std::unique_ptr<Intersector> inner_;

  private:
    const Derived& self() const { return static_cast<const Derived&>(*this); }
};

}  // namespace foton
