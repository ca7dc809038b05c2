#pragma once
// One interface for every ray-tracing backend (brute, grid, embree): a RayBatch in, closest
// hits (HitBatch) or an occlusion mask out. All backends must agree hit for hit; the tests
// hold them to it.
#include <cstdint>
#include <memory>
#include <vector>

#include "engine/core/ray_batch.h"
#include "engine/core/stats.h"
#include "engine/scene/scene.h"
#include "kernels/ray1.h"

namespace foton {

struct Hit1 {
    float t = kInfinity;
    float u = 0.f, v = 0.f;
    uint32_t prim = kNoHit;
    uint32_t geom = kNoHit;
};

class Intersector {
  public:
    virtual ~Intersector() = default;
    virtual const char* name() const = 0;
    // Closest hit per ray with tmin < t < tmax; hits.geom[i] == kNoHit for a miss.
    virtual void intersect(const RayBatch& rays, HitBatch& hits, TraceCounters& c) const = 0;
    // occluded[i] = 1 when anything lies strictly between tmin and tmax.
    virtual void occluded(const RayBatch& rays, std::vector<uint8_t>& occluded,
                          TraceCounters& c) const = 0;
    // Single-ray forms, for tests and tools.
    virtual bool intersect1(const kern::Ray1& ray, Hit1& hit, TraceCounters& c) const = 0;
    virtual bool occluded1(const kern::Ray1& ray, TraceCounters& c) const = 0;
    virtual std::size_t memory_bytes() const = 0;
};

// Builds the backend over the scene's geometry (the scene must outlive it). `threads` bounds
// the threads the build (and Embree's own task system) may use; 0 = all hardware threads.
std::unique_ptr<Intersector> make_intersector(const Scene& scene, AccelType type, int threads = 0);

inline kern::Ray1 ray_at(const RayBatch& b, std::size_t i) {
    return {b.ox[i], b.oy[i], b.oz[i], b.dx[i], b.dy[i], b.dz[i], b.tmin[i], b.tmax[i]};
}

// Entry i of a batch's hits set to h.
inline void store_hit(HitBatch& hits, std::size_t i, const Hit1& h) {
    hits.t[i] = h.t;
    hits.u[i] = h.u;
    hits.v[i] = h.v;
    hits.prim[i] = h.prim;
    hits.geom[i] = h.geom;
}

// Implements the batch entry points by looping a backend's single-ray methods.
template <class Derived>
class PerRayIntersector : public Intersector {
  public:
    void intersect(const RayBatch& rays, HitBatch& hits, TraceCounters& c) const override {
        hits.resize(rays.size());
        const Derived& self = static_cast<const Derived&>(*this);
        for (std::size_t i = 0; i < rays.size(); ++i) {
            Hit1 h;
            self.closest(ray_at(rays, i), h, c);
            store_hit(hits, i, h);
        }
    }
    void occluded(const RayBatch& rays, std::vector<uint8_t>& occ,
                  TraceCounters& c) const override {
        occ.resize(rays.size());
        const Derived& self = static_cast<const Derived&>(*this);
        for (std::size_t i = 0; i < rays.size(); ++i) occ[i] = self.any(ray_at(rays, i), c);
    }
    bool intersect1(const kern::Ray1& ray, Hit1& hit, TraceCounters& c) const override {
        return static_cast<const Derived&>(*this).closest(ray, hit, c);
    }
    bool occluded1(const kern::Ray1& ray, TraceCounters& c) const override {
        return static_cast<const Derived&>(*this).any(ray, c);
    }
};

}  // namespace foton
