#pragma once
// Shading of Lambertian path vertices as one SoA kernel (issue 35; Áfra et al., "Local shading
// coherence extraction for SIMD-efficient path tracing on CPUs", HPG 2016): the path tracer
// sorts a bounce's hits by material kind, writes the Lambertian ones into a ShadeTable, and
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
// A lane may carry a glossy lobe too (kDvGlossKind: modified Phong, Beckmann or cos^e
// microfacets with a Fresnel term; glossy_lanes.h), alone or beside the diffuse lobe: f is
// then the lobes' sum and the pdf their densities mixed by the sampling weights (Bsdf::f,
// Bsdf::pdf), and the continuation picks a lobe by kDvUChoice in the BSDF's order and samples
// it (Bsdf::sample). Its powers, exponentials and logarithms are glossy_math.h's polynomials.
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

#include "shade_table.h"

namespace foton::kern {

// How the light sample is weighed against BSDF sampling (engine/transport/common/mis.h).
enum class DiffuseMis : uint8_t { Balance, Power, Maximum, Mean, None };

struct DiffuseRules {
    DiffuseMis mis = DiffuseMis::Power;  // Power: exponent 2
    bool roulette = false;               // Russian roulette at this bounce
};

// Lanes [0, n) of `v`; lanes up to n rounded to the SIMD width are computed too, so the
// caller pads (any finite values) and ignores them.
void shade_diffuse(const ShadeTable& v, std::size_t n, const DiffuseRules& rules);
void shade_diffuse_scalar(const ShadeTable& v, std::size_t n, const DiffuseRules& rules);

}  // namespace foton::kern
