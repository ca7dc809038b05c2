#pragma once
// The parameters of a hair fibre (Chiang, Bitterli, Tappan and Burley 2016, as pbrt-v4's
// `hair` material): a dielectric cylinder of index eta with tilted cuticle scales, absorbing
// sigma_a per unit radius inside; beta_m and beta_n its longitudinal and azimuthal roughness.
// h is where the ray met the fibre across its width, -1 to 1 (set at each hit from the
// curve's v).
#include "engine/core/rgb.h"

namespace foton {

struct HairFiber {
    RGB sigma_a{0.f};
    float eta = 1.55f;
    float beta_m = 0.3f, beta_n = 0.3f;
    float alpha_degrees = 2.f;  // the scales' tilt
    float h = 0.f;
};

// pbrt-v4's melanin absorption: eumelanin and pheomelanin concentrations to sigma_a.
RGB hair_sigma_a_from_melanin(float eumelanin, float pheomelanin);
// Chiang et al.'s inversion: the absorption that gives a fibre of azimuthal roughness beta_n
// this multiple-scattering colour (each channel below 1).
RGB hair_sigma_a_from_reflectance(const RGB& c, float beta_n);

}  // namespace foton
