#pragma once
// Brute force: every ray against every triangle (in SIMD blocks) and every sphere. The
// baseline of the thesis' first measurement and the oracle of the accelerator tests.
#include <vector>

#include "intersector.h"
#include "kernels/triangle_block.h"

namespace foton {

class BruteAccel final : public PerRayIntersector<BruteAccel> {
public:
    explicit BruteAccel(const Scene& scene);
    const char* name() const override { return "brute"; }
    std::size_t memory_bytes() const override;

    bool closest(const kern::Ray1& ray, Hit1& hit, TraceCounters& c) const;
    bool any(const kern::Ray1& ray, TraceCounters& c) const;

private:
    struct MeshBlocks {
        uint32_t geom;
        std::vector<kern::TriangleBlock> blocks;
    };
    const Scene& scene_;
    std::vector<MeshBlocks> meshes_;
    std::vector<uint32_t> sphere_objects_;
};

}  // namespace foton
