#pragma once
// Image error metrics for comparing renders with each other and with references.
#include <cstdint>
#include <string>
#include <vector>

#include "film.h"

namespace foton {

struct ImageError {
    double rmse = 0.0;          // sqrt(mean over pixels and channels of (a - b)^2)
    double relative_mse = 0.0;  // mean of (a - b)^2 / (b^2 + 1e-2), per channel
    double mae = 0.0;           // mean |a - b|
    double max_abs = 0.0;       // largest |a - b| of any channel; NaN when one is NaN
    std::size_t pixels = 0;     // pixels counted (mask)
    // Counted pixels with a NaN or infinite channel, in a and in b: they make the other
    // figures NaN or infinite, and say the render (or the reference) is broken.
    std::size_t nonfinite_a = 0, nonfinite_b = 0;
    RGB mean_a, mean_b;  // channel means over the counted pixels
};

// `mask` (optional, same size as the images) selects the pixels that count.
ImageError compare_images(const Film& a, const Film& b, const std::vector<uint8_t>* mask = nullptr);

// Box-filters `f` down by an integer factor (each output pixel the mean of factor^2
// pixels): a reference rendered with a 1-pixel box filter at N times the resolution becomes
// the box-filtered reference at the lower resolution, exactly.
Film downsample(const Film& f, int factor);

// The reference `ref` (read from `path`) at width x height: as it is, or box-filtered down
// when it is an integer multiple of that size. Other sizes are bad input (InputError).
Film fit_reference(Film ref, int width, int height, const std::string& path);

// Mask of the pixels whose luminance in `ref` is at most `max_luminance` (e.g. to leave the
// directly seen light out of an error figure).
std::vector<uint8_t> luminance_mask(const Film& ref, float max_luminance);
// Also leaves out every pixel within `margin` pixels (Chebyshev distance) of one the mask
// leaves out: a light's partly covered edge pixels are dimmer than the cut, yet at low spp
// they are all or nothing, and would dominate the error of the rest.
std::vector<uint8_t> grow_exclusion(const std::vector<uint8_t>& mask, int width, int height,
                                    int margin);

// RMSE of the error after an n x n box filter (every window, sliding, that lies wholly in the
// mask): the noise that is left when neighbouring pixels are averaged, as the eye does from a
// distance. Samplers that make neighbours' errors cancel (blue noise, sampler="zsobol") lower
// it more than the plain RMSE; n = 1 is the RMSE.
double lowpass_rmse(const Film& a, const Film& b, const std::vector<uint8_t>& mask, int n);

}  // namespace foton
