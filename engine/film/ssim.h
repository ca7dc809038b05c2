#pragma once
// Structural similarity (SSIM): an error figure closer to what the eye sees than RMSE, from
// Z. Wang, A. C. Bovik, H. R. Sheikh and E. P. Simoncelli, "Image Quality Assessment: From
// Error Visibility to Structural Similarity", IEEE Transactions on Image Processing 13(4),
// 600-612, 2004. 1 for equal images, lower as structure, contrast or brightness differ.
#include <cstdint>
#include <vector>

#include "film.h"

namespace foton {

// SSIM is defined on display values in [0, 1]: each pixel's luminance (Rec. 709 weights) times
// `exposure`, clamped to [0, 1] and raised to 1 / `gamma`, as the PNG preview shows it. The
// paper's settings: an 11 x 11 Gaussian window of sigma 1.5 (smaller for images under 11
// pixels a side), K1 = 0.01, K2 = 0.03, L = 1; the figure is the mean over every window that
// lies wholly in the image and whose centre `mask` (optional) keeps. NaN pixels count as 0
// (foton compare reports them separately). NaN when no window counts.
double ssim(const Film& a, const Film& b, const std::vector<uint8_t>* mask = nullptr,
            float exposure = 1.f, float gamma = 2.2f);

}  // namespace foton
