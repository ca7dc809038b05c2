#pragma once
// Octrees, nested as the grids are: a binary BVH over the scene's objects (meshes and
// spheres) and inside each mesh its own triangle octree (kernels/triangle_octree.h), so one
// dense mesh in a large scene gets an octree of its own size. The ray-tracing thesis' third
// accelerator beside the uniform grid and the BVH, for kernel studies (--accel octree).
#include <vector>

#include "instance_layer.h"
#include "intersector.h"
#include "kernels/bvh_build.h"
#include "kernels/triangle_octree.h"

namespace foton {

class OctreeAccel final : public PerRayIntersector<OctreeAccel> {
  public:
    explicit OctreeAccel(const Scene& scene, const kern::OctreeParams& params = {});
    const char* name() const override { return "octree"; }
    std::size_t memory_bytes() const override;

    bool closest(const kern::Ray1& ray, Hit1& hit, TraceCounters& c) const;
    bool any(const kern::Ray1& ray, TraceCounters& c) const;

  private:
    const Scene& scene_;
    std::vector<kern::TriangleOctree> octrees_;  // by mesh index (instanced meshes: empty)
    kern::BinaryBvh objects_;                    // over the objects that are not instanced
    InstanceLayer instances_;                    // BLAS: octrees of the instanced meshes
};

}  // namespace foton
