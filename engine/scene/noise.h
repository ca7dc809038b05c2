#pragma once
// Perlin's gradient noise ("Improving noise", SIGGRAPH 2002: the quintic fade and his
// permutation table) and the sums pbrt-v4's procedural textures build from it: fractional
// Brownian motion (fbm) and turbulence (wrinkled). Without ray footprints every octave is
// summed (pbrt-v4 drops the octaves finer than a pixel's footprint). The gradients are
// Perlin's reference set; pbrt-v4 picks others for 4 of the 16 hashes: the same kind of
// noise, not the same pattern.
#include "engine/core/math.h"

namespace foton {

// Gradient noise in about [-1, 1], 0 at every integer lattice point.
float perlin_noise(const Vec3& p);
// Sum of octaves k = 0..octaves-1 of omega^k noise(1.99^k p).
float fbm(const Vec3& p, float omega, int octaves);
// The same of |noise|, plus pbrt-v4's 0.2 omega^octaves for the partial octave it adds.
float turbulence(const Vec3& p, float omega, int octaves);

}  // namespace foton
