#pragma once
// Brute force: every ray against every triangle and every sphere, the baseline of the
// thesis' first measurement and the oracle of the accelerator tests. The triangles are kept
// in SIMD blocks; `simd` chooses between the SIMD kernel and its scalar twin (the thesis'
// brute force), which give bit-identical hits.
#include <vector>

#include "instance_layer.h"
#include "intersector.h"
#include "kernels/triangle_block.h"

namespace foton {

class BruteAccel final : public PerRayIntersector<BruteAccel> {
  public:
    BruteAccel(const Scene& scene, bool simd);
    const char* name() const override { return simd_ ? "brute-simd" : "brute"; }
    std::size_t memory_bytes() const override;

    bool closest(const kern::Ray1& ray, Hit1& hit, TraceCounters& c) const;
    bool any(const kern::Ray1& ray, TraceCounters& c) const;

  private:
    struct MeshBlocks {
        uint32_t geom;
        std::vector<kern::TriangleBlock> blocks;
    };
    const Scene& scene_;
    bool simd_;
    std::vector<MeshBlocks> meshes_;
    std::vector<uint32_t> sphere_objects_;
    InstanceLayer instances_;  // BLAS of the same kind
};

}  // namespace foton
