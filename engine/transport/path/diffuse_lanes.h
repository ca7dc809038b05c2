#pragma once
// What the path tracer's SIMD shading of Lambertian vertices keeps (path_diffuse.cpp): which
// materials the kernel takes, fixed when the integrator is made, and a workspace's table of
// lanes, kern::shade_diffuse's columns.
#include <cstdint>
#include <vector>

#include "engine/core/aligned.h"
#include "engine/core/rgb.h"
#include "kernels/diffuse_shade.h"

namespace foton {

struct DiffuseMaterials {
    bool enabled = false;        // the settings and the vertex rules allow the kernel at all
    std::vector<uint8_t> takes;  // per material: Lambertian lobes only, untextured, not emitting
    std::vector<RGB> rho;        // ... and their summed reflectance
    kern::DiffuseRules rules;
};

struct DiffuseLanes {
    // Lanes per kernel call: the table (95 columns, 24 KB) stays in the first-level cache
    // between filling it, the kernel and reading it back.
    static constexpr std::size_t kLanes = 64;
    AlignedVector<float> data = AlignedVector<float>(std::size_t(kern::kDiffuseColumns) * kLanes);
    uint32_t entry[kLanes];  // the batch entry each lane came from
    std::size_t size = 0;
    // The lanes' random numbers of this bounce, drawn as one table when every lane's sampler
    // is counter-based, Sobol' or Z-Sobol' (kRandRows rows of kLanes; `drawn` says whether they
    // are). The rows are the Sobol' table's: the pairs (light point), (BSDF direction), (light
    // choice, mesh triangle), (lobe, roulette).
    static constexpr uint32_t kRandRows = 8;
    static constexpr uint32_t kRandLight = 0, kRandBsdf = 2, kRandLightSelect = 4, kRandLightUc = 5,
                              kRandRoulette = 7;
    AlignedVector<uint64_t> keys = AlignedVector<uint64_t>(kLanes);
    AlignedVector<uint64_t> z_index = AlignedVector<uint64_t>(kLanes);
    AlignedVector<uint32_t> pattern_index = AlignedVector<uint32_t>(kLanes);
    AlignedVector<uint32_t> pattern_count = AlignedVector<uint32_t>(kLanes);
    AlignedVector<float> rand = AlignedVector<float>(std::size_t(kRandRows) * kLanes);
    bool drawn = false;

    kern::DiffuseVertices table() { return {data.data(), kLanes}; }
    float* col(uint32_t c) { return data.data() + std::size_t(c) * kLanes; }
};

}  // namespace foton
