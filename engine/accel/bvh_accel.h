#pragma once
// Our wide BVH as a backend (kernels/triangle_bvh.h): one tree over the triangles of every mesh
// of the scene, so a dense mesh in a large sparse scene costs nothing extra, and a small binary
// BVH over the spheres, traversed after it. Closest hits are the least (t, geometry, primitive)
// over the scene, exactly what brute force returns, so every image equals brute force's bit for
// bit, ties included.
#include <vector>

#include "instance_layer.h"
#include "intersector.h"
#include "kernels/bvh_build.h"
#include "kernels/triangle_bvh.h"

namespace foton {

class BvhAccel final : public PerRayIntersector<BvhAccel> {
  public:
    // Incoherent batches go through the stream kernels when the triangle tree is larger than
    // this; below it, ray by ray. Measured with bench/compare_embree and foton render --stats
    // (docs/kernels.md): the interleaved stream's prefetching pays where nodes miss the caches
    // (the dragon's 52 MB tree: 1.2x on diffuse rays) and costs up to 30 % on trees the caches
    // hold; shadow batches of an image tile, ordered by octant and origin, go through the
    // packet kernel (the dragon's occlusion stage: 1.1x over the interleaved stream; on the
    // Cornell box's one-leaf tree packets were 1.5x slower than single rays).
    static constexpr std::size_t kStreamMinBytes = std::size_t(8) << 20;

    // `threads` bounds the parallel build (0: all hardware threads); `stream_min_bytes` is the
    // rule above (tests pass 0 to send every incoherent batch through the stream).
    BvhAccel(const Scene& scene, int threads, std::size_t stream_min_bytes = kStreamMinBytes);
    const char* name() const override { return "bvh"; }
    std::size_t memory_bytes() const override;

    bool closest(const kern::Ray1& ray, Hit1& hit, TraceCounters& c) const;
    bool any(const kern::Ray1& ray, TraceCounters& c) const;

    // A coherent batch (camera rays) goes through the packet traversal, W rays at a time; an
    // incoherent one through a stream form when the tree is larger than the caches (use_stream:
    // interleaved for closest hits, sorted packets for occlusion), else ray by ray. All give
    // every ray its single-ray answer.
    void intersect(const RayBatch& rays, HitBatch& hits, TraceCounters& c) const override;
    void occluded(const RayBatch& rays, std::vector<uint8_t>& occluded,
                  TraceCounters& c) const override;

    const kern::TriangleBvh& triangles() const { return tris_; }

  private:
    bool use_stream(const RayBatch& rays) const;
    // Updates `hit` with the nearest sphere before it (ties to the smaller geometry id among
    // spheres; a triangle at the same t keeps the hit, as in brute force).
    void closest_sphere(const kern::Ray1& ray, Hit1& hit, TraceCounters& c) const;
    bool any_sphere(const kern::Ray1& ray, TraceCounters& c) const;
    // The mesh hit of a triangle id of the tree.
    Hit1 mesh_hit(const kern::TriHit& th) const;
    // Ray i of a batch finished from its triangle hit (valid or not) as closest() finishes a
    // ray: the mesh hit, then spheres and instances; written to hits[i].
    void finish_hit(const RayBatch& rays, std::size_t i, const kern::TriHit& th, HitBatch& hits,
                    TraceCounters& c) const;

    const Scene& scene_;
    kern::TriangleBvh tris_;
    std::vector<uint32_t> first_id_;   // per mesh object in geometry order: its first triangle id
    std::vector<uint32_t> mesh_geom_;  // the geometry id of each of those
    kern::BinaryBvh spheres_;          // over sphere objects; prims are geometry ids
    InstanceLayer instances_;          // BLAS: wide BVHs of the instanced meshes
    std::size_t stream_min_bytes_;
};

}  // namespace foton
