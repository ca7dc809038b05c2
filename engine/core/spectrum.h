#pragma once
// Spectral rendering's wavelengths and colorimetry. A spectral path carries three wavelengths
// (the hero-wavelength scheme of Wilkie et al. 2014: one sampled, the other two a third of the
// visible range further on, wrapping round) and its throughput's value at each in the slots of
// an RGB triple: slot r holds lambda[0]'s, g lambda[1]'s, b lambda[2]'s. Every product and sum
// of the transport is per slot, so the RGB code carries spectral values unchanged; what changes
// is where a colour enters (a reflectance, a coefficient, an emitter: upsampled to a spectrum
// and read at the three wavelengths, rgb_spectrum.h) and where a sample leaves (to CIE XYZ by
// the colour matching functions, then to linear sRGB, to_rgb).
//
// Radiometry follows pbrt-v4's spectral mode, so the two agree on the same files: an emitter's
// RGB is a spectrum shaped like illuminant D65 (the sRGB white) and normalised to luminance 1
// for RGB (1, 1, 1), so a white emitter seen directly is (1, 1, 1) and a reflectance's RGB under
// it is the reflectance.
#include "colorimetry.h"
#include "rgb.h"

namespace foton {

// The density foton samples wavelengths by: a sech^2 bump over the visible range [360, 830] nm
// (the shape pbrt-v4 samples by, after Radziszewski et al.), so the colour matching functions'
// tails take few samples.
float visible_wavelength_pdf(float lambda);
float sample_visible_wavelength(float u);

struct Wavelengths {
    float lambda[3] = {0.f, 0.f, 0.f};
    float pdf[3] = {0.f, 0.f, 0.f};
    float d65[3] = {0.f, 0.f, 0.f};  // d65_normalised at each, for illuminant()
    bool secondary_terminated = false;

    // Keeps lambda[0] alone from here on (pbrt-v4's TerminateSecondary, at a dispersive
    // glass): the path's throughput `beta` in the other slots is dropped and lambda[0]'s
    // counted three times, so to_rgb's (1/3) sum becomes the one wavelength's estimate, which
    // is unbiased as lambda[0] alone has the sampling density. Once a path; what the path
    // gathered before is untouched.
    void terminate_secondary(RGB& beta) {
        if (secondary_terminated) return;
        secondary_terminated = true;
        beta = RGB{3.f * beta.r, 0.f, 0.f};
    }

    // The three wavelengths of one path from u in [0, 1).
    static Wavelengths sample(float u);
    // A path's values at the three wavelengths to linear sRGB: the estimate of the integral of
    // the colour matching functions times the spectrum, (1/3) sum cmf(lambda_i) L_i / pdf_i.
    RGB to_rgb(const RGB& values) const;
    // An RGB quantity as a spectrum at the three wavelengths (rgb_spectrum.h): a reflectance
    // (bounded by 1 when every channel is; a brighter one is taken as unbounded), an unbounded
    // quantity (a medium's coefficients, an index), an emitter's radiance (the unbounded
    // spectrum times normalised D65).
    RGB reflectance(const RGB& rgb) const;
    RGB unbounded(const RGB& rgb) const;
    RGB illuminant(const RGB& rgb) const;
};

}  // namespace foton
