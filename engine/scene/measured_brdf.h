#pragma once
// pbrt-v4's "measured" material: a BRDF of the RGL material database (Dupuy and Jakob 2018,
// "An adaptive parameterization for efficient material acquisition and rendering"), read from
// its `.bsdf` tensor file (core/tensor_file.h). The file holds the microfacet distribution D
// and the projected area sigma(wo) over the unit square, and per incident direction
// (phi_i, theta_i) a visible-normal warp, a luminance warp and the spectra measured in the
// visible-normal warp's sample space (core/warp_2d.h); the BRDF is
//   f(wo, wi) = fr(u) D(wm) / (4 sigma(wo) cos theta_i),
// with u the sample the visible-normal warp maps to the half vector wm, and sampling runs the
// luminance warp and then the visible-normal warp, as pbrt-v4 does. Directions map to the unit
// square by u = sqrt(2 theta / pi) and v = phi / (2 pi) + 1/2 (phi relative to the incident
// direction's for an isotropic material). foton reads the spectra as linear sRGB (integrated
// once at load against the CIE functions times D65, so a constant spectrum is grey) or, on a
// spectral path, at its wavelengths.
#include <memory>
#include <string>

#include "engine/core/math.h"
#include "engine/core/rgb.h"
#include "engine/core/tensor_file.h"
#include "engine/core/warp_2d.h"

namespace foton {

struct MeasuredBrdf {
    std::string path;
    bool isotropic = true;
    Warp2D ndf, sigma, vndf, luminance;
    Warp2D spectra;  // parameters phi_i, theta_i, wavelength (nm)
    Warp2D rgb;      // parameters phi_i, theta_i, channel (0, 1, 2): the spectra as linear sRGB

    // wo, wi in the shading frame; `lambda` (three wavelengths) or null for RGB.
    RGB f(const Vec3& wo, const Vec3& wi, const float* lambda) const;
    float pdf(const Vec3& wo, const Vec3& wi) const;
    bool sample(const Vec3& wo, Point2 u, const float* lambda, Vec3& wi, RGB& f, float& pdf) const;

  private:
    struct Pair;
    bool pair(const Vec3& wo, const Vec3& wi, Pair& q) const;
};

// The BRDF of .bsdf file `path`; InputError(path, 0, ...) when it is not one.
std::shared_ptr<const MeasuredBrdf> load_measured_brdf(const std::string& path);
// The same from a tensor file already read.
std::shared_ptr<const MeasuredBrdf> measured_brdf_from(const TensorFile& file);

}  // namespace foton
