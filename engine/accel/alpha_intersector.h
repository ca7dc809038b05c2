#pragma once
// Alpha cut-outs for every backend: a wrapper that asks the backend for the closest hit and,
// where that hit lies on a cut-out point of its material (Material::alpha), asks again from
// just past it, until a hit counts or the ray leaves. The alpha test is a function of the ray
// and the hit alone (pbrt-v4's: a hash of the ray's origin and direction against the alpha),
// so every backend, Embree included, every thread count and every MPI rank find the same
// hits. Occlusion: an unoccluded ray stays so (cut-outs only remove hits); an occluded one is
// confirmed by that closest-hit walk.
#include <memory>

#include "intersector.h"

namespace foton {

// Whether a hit on geometry `geom` (primitive `prim`, barycentrics or sphere point by t)
// counts for a ray from o along d that has passed `passed` cut-out points before it: its
// material is opaque there, or the hash of the ray and the count passes.
bool alpha_hit_counts(const Scene& scene, uint32_t geom, uint32_t prim, float t, float u, float v,
                      const Vec3& o, const Vec3& d, uint32_t passed);

class AlphaIntersector final : public Intersector {
  public:
    AlphaIntersector(const Scene& scene, std::unique_ptr<Intersector> inner)
        : scene_(scene), inner_(std::move(inner)) {}
    const char* name() const override { return inner_->name(); }
    void intersect(const RayBatch& rays, HitBatch& hits, TraceCounters& c) const override;
    void occluded(const RayBatch& rays, std::vector<uint8_t>& occluded,
                  TraceCounters& c) const override;
    bool intersect1(const kern::Ray1& ray, Hit1& hit, TraceCounters& c) const override;
    bool occluded1(const kern::Ray1& ray, TraceCounters& c) const override;
    std::size_t memory_bytes() const override { return inner_->memory_bytes(); }

  private:
    // Re-traces the rays of `rays` whose hits in `hits` are cut out, from just past them;
    // `tmax` bounds each (the original ray's).
    void resolve(const RayBatch& rays, HitBatch& hits, TraceCounters& c) const;
    const Scene& scene_;
    std::unique_ptr<Intersector> inner_;
};

}  // namespace foton
