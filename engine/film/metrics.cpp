#include "metrics.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace foton {

ImageError compare_images(const Film& a, const Film& b, const std::vector<uint8_t>* mask) {
    if (a.width != b.width || a.height != b.height)
        throw std::invalid_argument("images differ in size");
    ImageError e;
    double se = 0.0, rel = 0.0, ae = 0.0;
    for (std::size_t i = 0; i < a.pixels.size(); ++i) {
        if (mask && !(*mask)[i]) continue;
        ++e.pixels;
        const float av[3] = {a.pixels[i].r, a.pixels[i].g, a.pixels[i].b};
        const float bv[3] = {b.pixels[i].r, b.pixels[i].g, b.pixels[i].b};
        for (int c = 0; c < 3; ++c) {
            const double d = double(av[c]) - double(bv[c]);
            se += d * d;
            rel += d * d / (double(bv[c]) * double(bv[c]) + 1e-2);
            ae += std::fabs(d);
            e.max_abs = std::max(e.max_abs, std::fabs(d));
        }
    }
    if (e.pixels > 0) {
        const double n = 3.0 * double(e.pixels);
        e.rmse = std::sqrt(se / n);
        e.relative_mse = rel / n;
        e.mae = ae / n;
    }
    return e;
}

}  // namespace foton
