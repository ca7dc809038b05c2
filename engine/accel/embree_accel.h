#pragma once
// Intel Embree 3 as a backend: the speed bar for our own kernels. Triangles are Embree
// triangle geometries; spheres are user geometries that call our own sphere test, so that
// sphere hits agree exactly with the other backends. Triangle hits are re-evaluated with our
// Möller–Trumbore on the triangle Embree found, so that t, u, v (and hence images) agree bit
// for bit with brute and grid; a benchmark of raw Embree lives in bench/. Batches go through
// the stream API (rtcIntersect1M / rtcOccluded1M), flagged coherent when the batch is.
// Instanced meshes are Embree instances of one child scene per shared mesh; their hits are
// re-evaluated in the instance's space with the ray transformed as the other backends do.
#include <embree3/rtcore.h>

#include <vector>

#include "intersector.h"

namespace foton {

class EmbreeAccel final : public PerRayIntersector<EmbreeAccel> {
  public:
    // `threads` limits Embree's device (its build); 0 = all hardware threads.
    explicit EmbreeAccel(const Scene& scene, int threads = 0);
    ~EmbreeAccel() override;
    EmbreeAccel(const EmbreeAccel&) = delete;
    EmbreeAccel& operator=(const EmbreeAccel&) = delete;
    const char* name() const override { return "embree"; }
    std::size_t memory_bytes() const override { return memory_; }

    bool closest(const kern::Ray1& ray, Hit1& hit, TraceCounters& c) const;
    bool any(const kern::Ray1& ray, TraceCounters& c) const;

    void intersect(const RayBatch& rays, HitBatch& hits, TraceCounters& c) const override;
    void occluded(const RayBatch& rays, std::vector<uint8_t>& occluded,
                  TraceCounters& c) const override;

  private:
    // Our Möller–Trumbore on the triangle Embree chose (see above).
    void reevaluate(const kern::Ray1& ray, Hit1& hit) const;

    const Scene& scene_;
    RTCDevice device_ = nullptr;
    RTCScene rtc_scene_ = nullptr;
    std::vector<RTCScene> child_scenes_;  // one per instanced mesh
    std::size_t memory_ = 0;
    // A hit's geometry id: the instance's when Embree went through one.
    static uint32_t geometry_of(const RTCHit& h) {
        return h.instID[0] != RTC_INVALID_GEOMETRY_ID ? h.instID[0] : h.geomID;
    }
};

}  // namespace foton
