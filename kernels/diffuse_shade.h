#pragma once
// Shading of Lambertian path vertices as one SoA kernel (issue 35; Áfra et al., "Local shading
// coherence extraction for SIMD-efficient path tracing on CPUs", HPG 2016): the path tracer
// sorts a bounce's hits by material kind, writes the Lambertian ones into these columns, and
// one call turns them into next event estimation's shadow rays and the paths' continuation
// rays at SIMD width.
//
// Per vertex (the path tracer's arithmetic, engine/transport/path/path.cpp, for a BSDF whose
// lobes are all Lambertian, reflectance rho):
//   light sample (given: the light chosen and sampled by the caller, pdf with its selection)
//     -> f = rho / pi on the viewer's side, the MIS weight against the cosine density, the
//        contribution beta f Li |cos| w / pdf and the shadow ray joining the pushed-off ends;
//   continuation: a cosine-weighted direction (Shirley-Chiu disc, Malley) in the frame of the
//     shading normal, beta *= f |cos| / pdf, Russian roulette on max(beta) * eta_scale, the
//     ray's origin pushed off the surface to the side it leaves by.
//
// Per vertex, first (unless given) the surface: the point, geometric and shading normals
// facing the ray and the offset, from a triangle's corners or a sphere.
//
// shade_diffuse is the xsimd kernel; shade_diffuse_scalar its scalar twin, written one lane at
// a time with branches. They do the same IEEE operations in the same order (sine and cosine
// by one polynomial, diffuse_shade_math.h; the build contracts no multiply-add), so the tests
// hold them to equality, bit for bit. The engine's own scalar shading (Bsdf::sample, libm's
// sin and cos) agrees to float rounding.
#include <cstddef>
#include <cstdint>

namespace foton::kern {

// The columns of a DiffuseVertices table (each `stride` floats, stride a multiple of the
// SIMD width).
enum DiffuseColumn : uint32_t {
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
    // The light sample: its pdf with the light's selection (0: none), 1 when it takes full
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
    // Or a rectangle light the kernel samples itself (kDvLrect = 1): kDvLightPdf is then the
    // light's selection probability alone, kDvLp its corner, kDvLn its normal (the side it
    // emits to), kDvLi its radiance, and these its edges, area and the two numbers that place
    // the point (LightSet::sample_li's arithmetic).
    kDvLrect,
    kDvLe1x,
    kDvLe1y,
    kDvLe1z,
    kDvLe2x,
    kDvLe2y,
    kDvLe2z,
    kDvLarea,
    kDvLu0,
    kDvLu1,
    // Uniform numbers: the BSDF direction (2), Russian roulette.
    kDvU0,
    kDvU1,
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
    // dielectric's index, the lobe's sampling weight, and the number that chooses between
    // reflection and refraction.
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
    kDvUChoice,
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
    kDiffuseColumns
};

// How the light sample is weighed against BSDF sampling (engine/transport/common/mis.h).
enum class DiffuseMis : uint8_t { Balance, Power, Maximum, None };

struct DiffuseRules {
    DiffuseMis mis = DiffuseMis::Power;  // Power: exponent 2
    bool roulette = false;               // Russian roulette at this bounce
};

// A column-major table: column c of lane i is data[c * stride + i].
struct DiffuseVertices {
    float* data = nullptr;
    std::size_t stride = 0;
    float* col(uint32_t c) const { return data + std::size_t(c) * stride; }
};

// Lanes [0, n) of `v`; lanes up to n rounded to the SIMD width are computed too, so the
// caller pads (any finite values) and ignores them.
void shade_diffuse(const DiffuseVertices& v, std::size_t n, const DiffuseRules& rules);
void shade_diffuse_scalar(const DiffuseVertices& v, std::size_t n, const DiffuseRules& rules);

// The SIMD width the kernel pads to.
std::size_t diffuse_shade_width();

}  // namespace foton::kern
