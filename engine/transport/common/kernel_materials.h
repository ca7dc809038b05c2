#pragma once
// Which shading kernel takes each material, fixed when an integrator is made, and a
// material's part of a kernel lane: the lobes as the kernels' columns read them
// (kernels/shade_table.h). The path tracer and the light tracer share them.
#include <cstdint>
#include <vector>

#include "engine/core/rgb.h"
#include "engine/scene/scene.h"
#include "kernel_lanes.h"
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

// Every material's kernel and columns, and each scene object's (enabled and rules are the
// integrator's to set).
KernelMaterials kernel_materials(const Scene& scene);

// A Diffuse material's columns (reflectance, Oren–Nayar's A and B, the glossy lobe) in lane
// `lane`; the glossy lobe's choice number is the caller's.
void put_diffuse_material(KernelLanes& L, std::size_t lane, const KernelMaterials& km,
                          uint32_t material);

}  // namespace foton
