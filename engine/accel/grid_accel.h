#pragma once
// Nested uniform grids, as the first thesis describes: a top-level grid over the scene's
// objects (meshes and spheres), and inside each mesh its own triangle grid (the SIMD kernel
// of kernels/uniform_grid.h). Nesting keeps a dense mesh in a large sparse scene ("teapot in
// a stadium") from collapsing into one cell of a scene-wide grid.
#include <vector>

#include "instance_layer.h"
#include "intersector.h"
#include "kernels/grid_dda.h"
#include "kernels/uniform_grid.h"

namespace foton {

class GridAccel final : public PerRayIntersector<GridAccel> {
  public:
    explicit GridAccel(const Scene& scene, const kern::GridParams& mesh_params = {});
    const char* name() const override { return "grid"; }
    std::size_t memory_bytes() const override;

    bool closest(const kern::Ray1& ray, Hit1& hit, TraceCounters& c) const;
    bool any(const kern::Ray1& ray, TraceCounters& c) const;

  private:
    // Closest hit in one object over the whole ray; updates `hit` if closer.
    bool hit_object(uint32_t geom, const kern::Ray1& ray, Hit1& hit, TraceCounters& c) const;
    bool occludes_object(uint32_t geom, const kern::Ray1& ray, TraceCounters& c) const;

    const Scene& scene_;
    std::vector<kern::UniformGrid> grids_;  // one per mesh object (indexed by mesh)
    kern::GridFrame top_;
    std::vector<uint32_t> cell_begin_;  // CSR over top-level cells
    std::vector<uint32_t> cell_objects_;
    InstanceLayer instances_;  // BLAS: grids of the instanced meshes
};

}  // namespace foton
