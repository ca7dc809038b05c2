#pragma once
// Intel Embree 3 as a backend: the speed bar for our own kernels. Triangles are Embree
// triangle geometries; spheres are user geometries that call our own sphere test, so that
// sphere hits agree exactly with the other backends. Triangle hits are re-evaluated with our
// Möller–Trumbore on the triangle Embree found, so that t, u, v (and hence images) agree bit
// for bit with brute and grid; a benchmark of raw Embree lives in bench/.
#include <embree3/rtcore.h>

#include "intersector.h"

namespace foton {

class EmbreeAccel final : public PerRayIntersector<EmbreeAccel> {
  public:
    explicit EmbreeAccel(const Scene& scene);
    ~EmbreeAccel() override;
    EmbreeAccel(const EmbreeAccel&) = delete;
    EmbreeAccel& operator=(const EmbreeAccel&) = delete;
    const char* name() const override { return "embree"; }
    std::size_t memory_bytes() const override { return memory_; }

    bool closest(const kern::Ray1& ray, Hit1& hit, TraceCounters& c) const;
    bool any(const kern::Ray1& ray, TraceCounters& c) const;

  private:
    const Scene& scene_;
    RTCDevice device_ = nullptr;
    RTCScene rtc_scene_ = nullptr;
    std::size_t memory_ = 0;
};

}  // namespace foton
