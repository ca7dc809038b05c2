#pragma once
// Shading of path vertices whose BSDF is one delta lobe, as one SoA kernel over the table of
// diffuse_shade.h (issue 35): a mirror (with no Fresnel term, a conductor's or a
// dielectric's) or a dielectric (reflection or refraction chosen by its Fresnel term against
// kDvUChoice, total internal reflection, radiance scaled by (eta_i / eta_t)^2 on the way
// through). Per vertex: the surface (unless given), the mirrored or refracted direction in
// the shading frame, beta *= f |cos| / pdf, the path's eta^2 product, Russian roulette on
// max(beta) times it, the ray's origin pushed off to the side it leaves by. No light sample:
// a delta lobe cannot be lit by one.
//
// shade_specular is the xsimd kernel, shade_specular_scalar its twin (the same IEEE
// operations in the same order: tested equal bit for bit); both follow bsdf.cpp's
// lobe_sample and Bsdf::sample and optics.h's Fresnel terms operation for operation, so the
// path tracer's images do not change.
#include <cstddef>

#include "diffuse_shade.h"

namespace foton::kern {

void shade_specular(const ShadeTable& v, std::size_t n, bool roulette);
void shade_specular_scalar(const ShadeTable& v, std::size_t n, bool roulette);

}  // namespace foton::kern
