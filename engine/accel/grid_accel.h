#pragma once
// Nested uniform grids, as the first thesis describes: a top-level grid over the scene's
// objects (meshes and spheres), and inside each mesh its own triangle grid (the SIMD kernel
// of kernels/uniform_grid.h). Nesting keeps a dense mesh in a large sparse scene ("teapot in
// a stadium") from collapsing into one cell of a scene-wide grid. Lazy (Scene::grid_lazy, the
// thesis' 8.1.1): a mesh's grid is built when the first ray reaches the mesh's box in the top
// grid, once (std::call_once), so meshes no ray reaches cost nothing; the grids are the eager
// ones, so the images are the same.
#include <atomic>
#include <memory>
#include <mutex>
#include <vector>

#include "instance_layer.h"
#include "intersector.h"
#include "kernels/grid_dda.h"
#include "kernels/uniform_grid.h"

namespace foton {

class GridAccel final : public PerRayIntersector<GridAccel> {
  public:
    explicit GridAccel(const Scene& scene, const kern::GridParams& mesh_params = {});
    // Mesh grids built so far (all of them unless lazy).
    std::size_t built_grids() const;
    std::size_t mesh_grids() const { return meshes_; }
    const char* name() const override { return "grid"; }
    std::size_t memory_bytes() const override;

    bool closest(const kern::Ray1& ray, Hit1& hit, TraceCounters& c) const;
    bool any(const kern::Ray1& ray, TraceCounters& c) const;

  private:
    // Closest hit in one object over the whole ray; updates `hit` if closer.
    bool hit_object(uint32_t geom, const kern::Ray1& ray, Hit1& hit, TraceCounters& c) const;
    bool occludes_object(uint32_t geom, const kern::Ray1& ray, TraceCounters& c) const;

    // Mesh `mesh`'s grid: eager grids were all built by the constructor, so the traversal reads
    // them without touching a once-flag; lazy ones are built by the first ray that comes.
    const kern::UniformGrid& grid(uint32_t mesh) const {
        return lazy_ ? build_once(mesh) : grids_[mesh];
    }
    const kern::UniformGrid& build_once(uint32_t mesh) const;

    const Scene& scene_;
    kern::GridParams mesh_params_;
    bool lazy_ = false;
    std::size_t meshes_ = 0;  // mesh objects that own a grid
    // One per mesh object (indexed by mesh); lazily filled under `once_`.
    mutable std::vector<kern::UniformGrid> grids_;
    mutable std::unique_ptr<std::once_flag[]> once_;
    mutable std::unique_ptr<std::atomic<bool>[]> built_;
    kern::GridFrame top_;
    std::vector<uint32_t> cell_begin_;  // CSR over top-level cells
    std::vector<uint32_t> cell_objects_;
    InstanceLayer instances_;  // BLAS: grids of the instanced meshes
};

}  // namespace foton
