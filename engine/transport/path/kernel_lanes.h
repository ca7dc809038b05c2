#pragma once
// What the path tracer's shading kernels keep (path_lanes.cpp): which kernel takes each
// material, fixed when the integrator is made, and a workspace's table of lanes, the kernels'
// columns (kernels/shade_table.h).
#include <cstdint>
#include <vector>

#include "engine/core/aligned.h"
#include "engine/core/math.h"
#include "engine/core/rgb.h"
#include "engine/scene/light_set.h"
#include "engine/transport/common/surface.h"
#include "kernels/diffuse_shade.h"

namespace foton {

// Which shading kernel takes a material's vertices.
enum class KernelKind : uint8_t {
    None,      // shade_vertex, one at a time
    Diffuse,   // kern::shade_diffuse: Lambertian lobes, or one Oren–Nayar or Lambertian lobe
               // with one Phong or microfacet lobe, or that glossy lobe alone
    Specular,  // kern::shade_specular: one mirror or dielectric lobe
};

// The diffuse kernel's lanes are grouped by their glossy lobe's kind (0: none), so that SIMD
// registers hold one kind's lanes (Áfra et al.'s coherence extraction, by a counting sort).
inline constexpr std::size_t kKernelGroups = 5;

// A specular material as kern::shade_specular reads it (the kDvSpec.. columns).
struct SpecularMaterial {
    float kind = 0.f;     // 1 mirror, 2 dielectric
    RGB color, transmit;  // reflection and transmission tints
    float fresnel = 0.f;  // 0 none, 1 conductor, 2 dielectric
    float ior = 1.f;
    RGB eta, k;  // a conductor's complex index
    float weight = 1.f;
};

// A diffuse kernel material's glossy lobe as kern::shade_diffuse reads it (the kDvGloss..
// columns, the Fresnel term in the kDvFresnel.. columns).
struct GlossyMaterial {
    float kind = 0.f;  // 0 none, kern::kGlossPhong, kGlossBeckmann, kGlossCosPower, kGlossGgx
    RGB color;
    float nu = 0.f, nv = 0.f;  // Phong's exponent or Beckmann's alpha; cos^e's exponents;
                               // GGX's alpha_x, alpha_y
    float diffuse_weight = 0.f, glossy_weight = 0.f;
    float glossy_first = 0.f;  // 1 when it comes before the diffuse lobe in the BSDF
    float fresnel = 0.f;       // 0 none, 1 conductor, 2 dielectric
    float ior = 1.f;
    RGB eta, k;
};

struct KernelMaterials {
    bool enabled = false;            // the settings and the vertex rules allow the kernels at all
    std::vector<KernelKind> kernel;  // per material; untextured and not emitting ones only
    std::vector<RGB> rho;            // Diffuse: the lobes' summed reflectance
    std::vector<float> on_a, on_b;   // ... and Oren–Nayar's A, B (Lambert: 1, 0)
    std::vector<SpecularMaterial> specular;
    std::vector<GlossyMaterial> glossy;  // Diffuse: a glossy lobe beside the diffuse one
    // By scene object (its material's), so grouping a hit is one lookup: the kernel, and
    // whether it is Diffuse with Lambertian lobes alone (the irradiance cache then takes its
    // first vertex, PathIntegrator::shade_cached).
    std::vector<KernelKind> object_kernel;
    std::vector<uint8_t> object_lambertian;
    std::vector<uint8_t> object_group;  // a Diffuse object's glossy kind, < kKernelGroups
    kern::DiffuseRules rules;
};

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

}  // namespace foton
