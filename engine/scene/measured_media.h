#pragma once
// Measured scattering coefficients of real materials, as published: Jensen, Marschner, Levoy
// and Hanrahan 2001 ("A Practical Model for Subsurface Light Transport", skin, milk,
// marble, ...) and Narasimhan, Gupta, Donner, Ramamoorthi, Nayar and Jensen 2006
// ("Acquiring Scattering Properties of Participating Media by Dilution", drinks and
// powders). Per millimetre, in RGB; the scattering coefficient is the reduced one
// (sigma_s (1 - g)), so a medium made from them scatters isotropically. pbrt-v4 names them
// the same way (its subsurface material's "name", its media's "preset").
#include <string>
#include <vector>

#include "engine/core/rgb.h"

namespace foton {

struct MeasuredMedium {
    const char* name;
    RGB sigma_s;  // reduced scattering, 1/mm
    RGB sigma_a;  // absorption, 1/mm
};

const std::vector<MeasuredMedium>& measured_media();
// By name; nullptr when there is none.
const MeasuredMedium* find_measured_medium(const std::string& name);
// "Apple, Chicken1, ...": for error messages.
std::string measured_media_names();

}  // namespace foton
