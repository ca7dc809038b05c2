#pragma once
// Conductors as the scene formats name them: measured metals by complex index of refraction
// per channel, and a conductor given by its reflectance at normal incidence.
#include <span>

#include "bsdf.h"

namespace foton {

struct Metal {
    const char* name;    // foton's XML preset
    const char* symbol;  // pbrt-v4's named spectra metal-<symbol>-eta / -k
    RGB eta, k;          // at about 650, 550 and 450 nm
};
std::span<const Metal> metals();

// A conductor of normal-incidence reflectance r (components in [0, 1]): eta = 1 and
// k = 2 sqrt(r / (1 - r)) give exactly r head-on and 1 at grazing angles (pbrt-v4's reading
// of a "reflectance" conductor). r is capped at 0.9999, where k stays finite.
Fresnel conductor_from_reflectance(const RGB& r);

}  // namespace foton
