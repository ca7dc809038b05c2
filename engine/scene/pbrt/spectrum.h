#pragma once
// pbrt-v4's spectra reduced to foton's linear sRGB: blackbody emitters, sampled
// (wavelength, value) spectra through the CIE 1931 matching functions (the 5 nm table,
// cie_1931.h), and pbrt-v4's named spectra
// (metals' eta and k, glasses' index of refraction, standard illuminants).
#include <optional>
#include <string>
#include <vector>

#include "engine/core/rgb.h"

namespace foton::pbrt {

// The colour of a blackbody at `kelvin`, scaled to luminance 1.
RGB blackbody_rgb(float kelvin);
// pbrt-v4's BlackbodySpectrum (Planck's law divided by its peak) as its film records it where
// nothing normalises it (the glow of a medium's temperature): the sum over 360..830 nm of the
// spectrum times the matching functions, in linear sRGB. Its luminance is that sum's Y.
RGB blackbody_emission_rgb(float kelvin);
// A spectrum given as (nm, value) pairs in increasing wavelength. Illuminants are scaled to
// luminance 1; reflectances keep their level (a flat spectrum of value v gives grey v).
RGB sampled_spectrum_rgb(const std::vector<float>& pairs, bool illuminant);
// A named spectrum ("metal-Cu-eta", "glass-BK7", "stdillum-D65"): its RGB (for glasses the
// index at 550 nm in every channel); nullopt for an unknown name.
std::optional<RGB> named_spectrum_rgb(const std::string& name);
// The names named_spectrum_rgb knows, for messages.
std::string named_spectrum_list();

}  // namespace foton::pbrt
