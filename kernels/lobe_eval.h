#pragma once
// The diffuse kernel's lobes (diffuse_lobes.h: Lambertian, Oren–Nayar, Phong and microfacet
// lobes, alone or mixed) evaluated at given pairs of local directions, one pair a lane: what
// vertex connection and merging (engine/transport/bidir/) ask of a BSDF at directions they
// did not sample. Per lane, with wo in kDvWo and wi in kDvLw (both unit, in the shading
// frame) and the material's columns: f(wo, wi) into kDvSv, Bsdf::pdf(wo, wi) into kDvNpdf and
// the reverse density Bsdf::pdf(wi, wo) into kDvPdfRev. Reflection lobes only, so f and the
// densities are the same in radiance and importance transport.
//
// eval_lobes is the xsimd kernel, eval_lobes_scalar its twin; equal bit for bit.
#include <cstddef>

#include "shade_table.h"

namespace foton::kern {

// Lanes [0, n) of `v` (lanes up to n rounded to the SIMD width are computed too).
void eval_lobes(const ShadeTable& v, std::size_t n);
void eval_lobes_scalar(const ShadeTable& v, std::size_t n);

}  // namespace foton::kern
