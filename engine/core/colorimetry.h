#pragma once
// The CIE colorimetry foton's spectral mode reads (core/spectrum.h): the 1931 colour matching
// functions, illuminant D65 and the map from CIE XYZ to linear sRGB, over the tables of
// cie_tables.h as interpolated linearly.
#include "rgb.h"

namespace foton {

// The CIE 1931 colour matching functions at lambda (x-bar, y-bar, z-bar as r, g, b), linear
// between the table's 5 nm steps, zero outside [360, 830] nm.
RGB cie_xyz(float lambda);
// Illuminant D65 at lambda, scaled so that its luminance (the integral of y-bar D65) is 1.
float d65_normalised(float lambda);
// CIE XYZ to linear sRGB (primaries of IEC 61966-2-1, white D65 from the tables above, so that
// the white emitter is (1, 1, 1) exactly).
RGB xyz_to_linear_srgb(const RGB& xyz);

}  // namespace foton
