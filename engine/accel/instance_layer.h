#pragma once
// Instanced meshes (Scene::instances) for the brute, grid and BVH backends: one structure per
// shared mesh (its BLAS), built by the backend's own kind over the mesh in its own space, and
// a binary BVH over the placements' world boxes (the TLAS). A ray goes into a placement's
// space through the inverse transform with its direction unnormalised, so its t is the world
// ray's. The backends consult the layer after their own geometry, so a hit they hold wins a
// tie with an instance; among instances, the first in TLAS order wins. The layer is the same
// for every backend and the BLAS kinds agree hit for hit, so the backends still agree with
// one another. (Embree instances natively, with the same ray transform: embree_accel.)
#include <memory>
#include <vector>

#include "intersector.h"
#include "kernels/bvh_build.h"

namespace foton {

// The world ray in the space of an instance.
kern::Ray1 to_instance_space(const Instance& in, const kern::Ray1& ray);

class InstanceLayer {
  public:
    InstanceLayer() = default;
    InstanceLayer(const Scene& scene, AccelType blas_type, int threads);
    bool empty() const { return tlas_.empty(); }
    // Replaces `hit` by the nearest instance hit nearer than it (and than ray.tmax).
    void closest(const kern::Ray1& ray, Hit1& hit, TraceCounters& c) const;
    bool any(const kern::Ray1& ray, TraceCounters& c) const;
    std::size_t memory_bytes() const;

  private:
    const Scene* scene_ = nullptr;
    // Per shared mesh: a scene holding only it (object 0, in its own space) and its BLAS.
    std::vector<std::unique_ptr<Scene>> prototypes_;
    std::vector<std::unique_ptr<Intersector>> blas_;
    std::vector<uint32_t> blas_of_mesh_;  // per Scene::meshes index, for instanced meshes
    kern::BinaryBvh tlas_;                // prims: geometry ids of instanced objects
};

}  // namespace foton
