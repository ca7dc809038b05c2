#pragma once
// Shading of the light tracer's vertices as one SoA kernel (issue 35): the diffuse kernel's
// lobes (diffuse_lobes.h: Lambertian, Oren–Nayar, Phong and microfacet lobes) with the camera
// in place of the light and importance in place of radiance. The light tracer
// (engine/transport/light/light_tracer.cpp) writes a bounce's hits on such materials into a
// ShadeTable; one call turns them into the connections to the camera and the paths'
// continuations at SIMD width.
//
// Per vertex (the light tracer's arithmetic), with wo the unit direction back towards the
// light (kDvWo), Veach's adjoint correction for shading normals adj = |wo.ns| / |wo.ng| (no
// vertex where wo grazes the geometric surface):
//   connection: wc the unit direction to the eye (kDvLp), on the side the light came from
//     (wc.ng > 0); the value beta f(wo, wc) adj (wc.ng) and the shadow ray from the surface,
//     pushed off towards wc, to the eye; the projection onto the film and the camera's
//     importance are the caller's;
//   continuation: Bsdf::sample, beta *= f adj |wi.ng| / pdf, Russian roulette on max(beta),
//     the ray's origin pushed off the surface to the side it leaves by.
// Out: kDvShadowValid, kDvSo, kDvSd, kDvStmax, kDvSv; kDvNextValid, kDvNo, kDvNd, kDvNbeta,
// kDvNpdf.
//
// shade_importance is the xsimd kernel, shade_importance_scalar its twin with branches; the
// same IEEE operations in the same order, equal bit for bit (diffuse_shade.h's contract).
#include <cstddef>

#include "shade_table.h"

namespace foton::kern {

// Lanes [0, n) of `v` (lanes up to n rounded to the SIMD width are computed too); roulette:
// Russian roulette at this bounce.
void shade_importance(const ShadeTable& v, std::size_t n, bool roulette);
void shade_importance_scalar(const ShadeTable& v, std::size_t n, bool roulette);

}  // namespace foton::kern
