#pragma once
// The table the shading kernels work on (diffuse_shade.h, specular_shade.h): one column per
// quantity, one lane per path vertex, filled by the path tracer (engine/transport/path/
// path_lanes.cpp) and read back after the kernel.
#include <cstddef>
#include <cstdint>

namespace foton::kern {

// The columns of a ShadeTable (each `stride` floats, stride a multiple of the SIMD width).
// kDv: a vertex's column; every shading kernel reads and writes its own subset.
// kDvLkind's values.
inline constexpr float kLightParallelogram = 1.f, kLightTriangle = 2.f, kLightSphere = 3.f;
// kDvGlossKind's values.
inline constexpr float kGlossPhong = 1.f, kGlossBeckmann = 2.f, kGlossCosPower = 3.f,
                       kGlossGgx = 4.f;

enum ShadeColumn : uint32_t {
    // The surface: position, geometric and shading normals (unit, facing the incoming ray),
    // the offset for rays leaving it, the unit direction back towards the viewer.
    kDvPx,
    kDvPy,
    kDvPz,
    kDvNgx,
    kDvNgy,
    kDvNgz,
    kDvNsx,
    kDvNsy,
    kDvNsz,
    kDvEps,
    kDvFront,  // 1 when the ray hit the side the geometry's normal points to
    kDvWox,
    kDvWoy,
    kDvWoz,
    // Or the hit to reconstruct that surface from (engine/transport/common/surface.cpp's
    // arithmetic), by kDvSurface: 0 = the columns above are given, 1 = a flat triangle,
    // 2 = a smooth one, 3 = a sphere. The ray's distance and barycentrics, its origin, the
    // triangle's corners (a sphere: its centre in A0, its radius in A1x) and a smooth
    // triangle's vertex normals. The kernel then writes the surface columns above.
    kDvSurface,
    kDvT,
    kDvU,
    kDvV,
    kDvOx,
    kDvOy,
    kDvOz,
    kDvA0x,
    kDvA0y,
    kDvA0z,
    kDvA1x,
    kDvA1y,
    kDvA1z,
    kDvA2x,
    kDvA2y,
    kDvA2z,
    kDvN0x,
    kDvN0y,
    kDvN0z,
    kDvN1x,
    kDvN1y,
    kDvN1z,
    kDvN2x,
    kDvN2y,
    kDvN2z,
    // Reflectance, the path's throughput up to here, its product of eta^2 (path.h).
    kDvRhoR,
    kDvRhoG,
    kDvRhoB,
    kDvBetaR,
    kDvBetaG,
    kDvBetaB,
    kDvEtaScale,
    // Oren–Nayar's A and B (a Lambertian material: 1 and 0, which is Lambert's f exactly).
    kDvOnA,
    kDvOnB,
    // A glossy lobe beside (or instead of) the diffuse one, kDvGlossKind: 0 none, 1 modified
    // Phong, 2 a Beckmann microfacet lobe, 3 a cos^e microfacet lobe (Blinn: nu = nv;
    // Ashikhmin–Shirley: nu along the shading frame's first tangent), 4 a Trowbridge–Reitz
    // (GGX) microfacet lobe (alpha_x in kDvGlossNu, alpha_y in kDvGlossNv; Smith's shadowing,
    // visible-normal sampling). Its tint (the
    // microfacet's Fresnel term in kDvFresnel.. below), Phong's exponent or Beckmann's slope
    // in kDvGlossNu, the cos^e exponents in kDvGlossNu and kDvGlossNv; both lobes' sampling
    // weights (a material without a diffuse lobe: 0 and rho 0) and 1 when the glossy lobe
    // comes first in the BSDF's order (Bsdf::sample's choice walks that order with
    // kDvUChoice).
    kDvGlossKind,
    kDvGlossR,
    kDvGlossG,
    kDvGlossB,
    kDvGlossNu,
    kDvGlossNv,
    kDvDiffuseWeight,
    kDvGlossWeight,
    kDvGlossFirst,
    // The light sample (shade_importance reads kDvLp as the camera's eye, the light of
    // importance transport): its pdf with the light's selection (0: none), 1 when it takes full
    // weight (a delta light, or no MIS), the unit direction to it, the distance (infinite for
    // a light at infinity), the sampled point and its normal facing the vertex, the radiance.
    kDvLightPdf,
    kDvLightFull,
    kDvLwx,
    kDvLwy,
    kDvLwz,
    kDvLdist,
    kDvLpx,
    kDvLpy,
    kDvLpz,
    kDvLnx,
    kDvLny,
    kDvLnz,
    kDvLiR,
    kDvLiG,
    kDvLiB,
    // Or a light the kernel samples itself (kDvLkind: 0 none, the sample above is given;
    // kLightParallelogram, a rectangle light; kLightTriangle, one triangle of an emissive mesh;
    // kLightSphere, a one-sided emitting sphere sampled in the cone it subtends). kDvLightPdf
    // is then the light's selection probability alone, kDvLi its radiance, kDvLp a
    // rectangle's or triangle's first corner (a sphere's centre), kDvLn its normal (the side
    // it emits to), kDvLe1/kDvLe2 a rectangle's edges or a triangle's other two corners
    // (kDvLe1x a sphere's radius), kDvLarea the area the point is uniform over (a whole
    // mesh's when its triangles are chosen by area), kDvLtwoSided whether it emits on both
    // sides, and kDvLu0/kDvLu1 the two numbers that place the point (LightSet::sample_li's
    // arithmetic).
    kDvLkind,
    kDvLe1x,
    kDvLe1y,
    kDvLe1z,
    kDvLe2x,
    kDvLe2y,
    kDvLe2z,
    kDvLarea,
    kDvLtwoSided,
    // The vertex's uniform numbers, in the order of the path tracer's number table (its rows
    // are these columns): the two that place a light's point, the BSDF direction's two, the
    // light's choice (read by the caller), the triangle of a mesh light chosen by area (the
    // caller's), the lobe's choice, Russian roulette.
    kDvLu0,
    kDvLu1,
    kDvU0,
    kDvU1,
    kDvULightSelect,
    kDvULightUc,
    kDvUChoice,
    kDvURoulette,
    // Out, the shadow ray and what it adds unoccluded (valid: 1 or 0).
    kDvShadowValid,
    kDvSox,
    kDvSoy,
    kDvSoz,
    kDvSdx,
    kDvSdy,
    kDvSdz,
    kDvStmax,
    kDvSvR,
    kDvSvG,
    kDvSvB,
    // A specular vertex's material (specular_shade.h): 1 = a mirror, 2 = a dielectric; its
    // reflectance tint, a dielectric's transmission tint, the mirror's Fresnel term (0 none,
    // 1 conductor of index eta + i k per channel, 2 dielectric of index kDvIor), a
    // dielectric's index, the lobe's sampling weight (kDvUChoice chooses between reflection
    // and refraction).
    kDvSpecKind,
    kDvSpecR,
    kDvSpecG,
    kDvSpecB,
    kDvTransR,
    kDvTransG,
    kDvTransB,
    kDvFresnel,
    kDvIor,
    kDvEtaR,
    kDvEtaG,
    kDvEtaB,
    kDvKR,
    kDvKG,
    kDvKB,
    kDvLobeWeight,
    // Out, the continuation (valid: 1 or 0), its throughput and solid-angle pdf.
    kDvNextValid,
    kDvNox,
    kDvNoy,
    kDvNoz,
    kDvNdx,
    kDvNdy,
    kDvNdz,
    kDvNbetaR,
    kDvNbetaG,
    kDvNbetaB,
    kDvNpdf,
    // Out, for a specular continuation: the path's product of eta^2 after it, and 1 when it
    // refracted.
    kDvNetaScale,
    kDvNtransmit,
    // Out, of kern::eval_lobes (lobe_eval.h): the density of sampling wo from wi.
    kDvPdfRev,
    kShadeColumns
};

// A column-major table: column c of lane i is data[c * stride + i].
struct ShadeTable {
    float* data = nullptr;
    std::size_t stride = 0;
    float* col(uint32_t c) const { return data + std::size_t(c) * stride; }
};

// The SIMD width the kernels pad a table's lanes to.
std::size_t shade_width();

}  // namespace foton::kern
