#pragma once
// A workspace's table of lanes for the shading kernels (kernels/shade_table.h's columns), as
// the path tracer (path/path_lanes.cpp) and the light tracer (light/light_tracer.cpp) fill
// and read it, and the hit's part of a lane that both write the same way.
#include <cstdint>
#include <vector>

#include "engine/core/aligned.h"
#include "engine/core/math.h"
#include "engine/core/ray_batch.h"
#include "engine/core/rgb.h"
#include "engine/scene/light_set.h"
#include "engine/scene/scene.h"
#include "engine/transport/common/surface.h"
#include "kernels/diffuse_shade.h"

namespace foton {

struct KernelLanes {
    // Lanes per kernel call: the table (95 columns, 24 KB) stays in the first-level cache
    // between filling it, the kernel and reading it back.
    static constexpr std::size_t kLanes = 64;
    AlignedVector<float> data = AlignedVector<float>(std::size_t(kern::kShadeColumns) * kLanes);
    uint32_t entry[kLanes];  // the batch entry each lane came from
    // The read-back's scratch: each lane's path slot, and the shadow rays' values packed.
    alignas(64) uint32_t slots[kLanes];
    alignas(64) uint32_t packed[3][kLanes];
    std::size_t size = 0;
    // The lanes' random numbers of this bounce, drawn as one table when every lane's sampler
    // is counter-based, Sobol', Z-Sobol' or Halton (kRandRows rows of kLanes, the columns
    // kDvLu0.. of `data`; `drawn` says whether they are). The rows are the Sobol' table's: the
    // pairs (light point), (BSDF direction), (light choice, mesh triangle), (lobe, roulette).
    static constexpr uint32_t kRandRows = 8;
    static constexpr uint32_t kRandLight = 0, kRandBsdf = 2, kRandLightSelect = 4, kRandLightUc = 5,
                              kRandLobe = 6, kRandRoulette = 7;
    AlignedVector<uint64_t> keys = AlignedVector<uint64_t>(kLanes);
    AlignedVector<uint64_t> z_index = AlignedVector<uint64_t>(kLanes);
    AlignedVector<uint32_t> z_bits = AlignedVector<uint32_t>(kLanes);
    AlignedVector<uint32_t> pattern_index = AlignedVector<uint32_t>(kLanes);
    AlignedVector<uint32_t> pattern_count = AlignedVector<uint32_t>(kLanes);
    bool drawn = false;
    // The lanes' surfaces where the CPU side makes them (surface_at): for a light sampled
    // before the kernel, and under the light BVH for every lane, first, so that the chunk's
    // lights are picked in one descent-kernel call (`picked` says whether they were).
    SurfacePoint surface[kLanes];
    LightPickLanes picks = LightPickLanes(kLanes);
    bool picked = false;

    // The number table's rows are the table's columns from kDvLu0 on, in the same order: the
    // kernels read the numbers where they were drawn.
    static_assert(kern::kDvLu0 + kRandLight == kern::kDvLu0 &&
                  kern::kDvLu0 + kRandBsdf == kern::kDvU0 &&
                  kern::kDvLu0 + kRandLightSelect == kern::kDvULightSelect &&
                  kern::kDvLu0 + kRandLightUc == kern::kDvULightUc &&
                  kern::kDvLu0 + kRandLobe == kern::kDvUChoice &&
                  kern::kDvLu0 + kRandRoulette == kern::kDvURoulette && kRandRows == 8);
    float* rand() { return col(kern::kDvLu0); }
    const float* rand() const { return data.data() + std::size_t(kern::kDvLu0) * kLanes; }

    kern::ShadeTable table() { return {data.data(), kLanes}; }
    float* col(uint32_t c) { return data.data() + std::size_t(c) * kLanes; }
    // Lane `lane` of columns c, c + 1, c + 2.
    void put3(uint32_t c, std::size_t lane, const Vec3& v) {
        col(c)[lane] = v.x;
        col(c + 1)[lane] = v.y;
        col(c + 2)[lane] = v.z;
    }
    void put3(uint32_t c, std::size_t lane, const RGB& v) { put3(c, lane, Vec3{v.r, v.g, v.b}); }
    Vec3 get3(uint32_t c, std::size_t lane) {
        return Vec3{col(c)[lane], col(c + 1)[lane], col(c + 2)[lane]};
    }
};

// The hit's geometry for the kernel to reconstruct the surface from (flat and smooth triangles
// of meshes placed as they are, spheres); false for an instance, whose surface the caller
// makes with surface_at and writes with put_surface.
bool put_hit(KernelLanes& L, std::size_t lane, const Scene& scene, const RayBatch& rays,
             const HitBatch& hits, std::size_t i);
// A surface made on the CPU side, written whole (kDvSurface 0).
void put_surface(KernelLanes& L, std::size_t lane, const SurfacePoint& sp);

}  // namespace foton
