#pragma once
// Spatial subdivisions of triangles, nested as the grids are: a binary BVH over the scene's
// objects (meshes and spheres) and inside each mesh its own tree, so one dense mesh in a large
// scene gets a tree of its own size. The ray-tracing thesis' chapter-8 accelerators beside the
// uniform grid and the BVH, for kernel studies: the octree (kernels/triangle_octree.h,
// --accel octree) and the SAH kd-tree (kernels/triangle_kdtree.h, --accel kdtree). A tree
// builds from a mesh's arrays and answers closest and any hits of single rays.
#include <vector>

#include "instance_layer.h"
#include "intersector.h"
#include "kernels/bvh_build.h"
#include "kernels/triangle_kdtree.h"
#include "kernels/triangle_octree.h"

namespace foton {

template <class Tree, AccelType kType>
class MeshTreeAccel final : public PerRayIntersector<MeshTreeAccel<Tree, kType>> {
  public:
    // threads > 0: build within that many threads (0: all).
    MeshTreeAccel(const Scene& scene, int threads);
    const char* name() const override { return accel_name(kType); }
    std::size_t memory_bytes() const override;

    bool closest(const kern::Ray1& ray, Hit1& hit, TraceCounters& c) const;
    bool any(const kern::Ray1& ray, TraceCounters& c) const;

  private:
    const Scene& scene_;
    std::vector<Tree> trees_;  // by mesh index (instanced meshes: empty)
    kern::BinaryBvh objects_;  // over the objects that are not instanced
    InstanceLayer instances_;  // BLAS: trees of the instanced meshes
};

using OctreeAccel = MeshTreeAccel<kern::TriangleOctree, AccelType::Octree>;
using KdTreeAccel = MeshTreeAccel<kern::TriangleKdTree, AccelType::KdTree>;

}  // namespace foton
