#include "metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "engine/core/error.h"

namespace foton {

ImageError compare_images(const Film& a, const Film& b, const std::vector<uint8_t>* mask) {
    if (a.width != b.width || a.height != b.height)
        throw std::invalid_argument("images differ in size");
    ImageError e;
    double se = 0.0, rel = 0.0, ae = 0.0;
    double ma[3] = {0, 0, 0}, mb[3] = {0, 0, 0};
    for (std::size_t i = 0; i < a.pixels.size(); ++i) {
        if (mask && !(*mask)[i]) continue;
        ++e.pixels;
        const float av[3] = {a.pixels[i].r, a.pixels[i].g, a.pixels[i].b};
        const float bv[3] = {b.pixels[i].r, b.pixels[i].g, b.pixels[i].b};
        auto finite = [](const float* v) {
            return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]);
        };
        e.nonfinite_a += !finite(av);
        e.nonfinite_b += !finite(bv);
        for (int c = 0; c < 3; ++c) {
            ma[c] += av[c];
            mb[c] += bv[c];
            const double d = double(av[c]) - double(bv[c]);
            se += d * d;
            rel += d * d / (double(bv[c]) * double(bv[c]) + 1e-2);
            ae += std::fabs(d);
            // std::max would drop a NaN difference and report the images equal.
            if (std::isnan(d) || std::isnan(e.max_abs))
                e.max_abs = std::numeric_limits<double>::quiet_NaN();
            else
                e.max_abs = std::max(e.max_abs, std::fabs(d));
        }
    }
    if (e.pixels > 0) {
        const double n = 3.0 * double(e.pixels);
        e.rmse = std::sqrt(se / n);
        e.relative_mse = rel / n;
        e.mae = ae / n;
        const double p = double(e.pixels);
        e.mean_a = RGB(float(ma[0] / p), float(ma[1] / p), float(ma[2] / p));
        e.mean_b = RGB(float(mb[0] / p), float(mb[1] / p), float(mb[2] / p));
    }
    return e;
}

Film fit_reference(Film ref, int width, int height, const std::string& path) {
    if (ref.width == width && ref.height == height) return ref;
    if (width > 0 && height > 0 && ref.width % width == 0 && ref.height % height == 0 &&
        ref.width / width == ref.height / height)
        return downsample(ref, ref.width / width);
    throw InputError(path, 0,
                     "image is " + std::to_string(ref.width) + "x" + std::to_string(ref.height) +
                         ", the render is " + std::to_string(width) + "x" + std::to_string(height) +
                         " (a reference must be that size or an "
                         "integer multiple of it)");
}

Film downsample(const Film& f, int factor) {
    if (factor < 1 || f.width % factor || f.height % factor)
        throw std::invalid_argument("image size is not a multiple of the factor");
    Film out(f.width / factor, f.height / factor);
    const float inv = 1.f / float(factor * factor);
    for (int y = 0; y < out.height; ++y)
        for (int x = 0; x < out.width; ++x) {
            RGB s;
            for (int j = 0; j < factor; ++j)
                for (int i = 0; i < factor; ++i) s += f.at(x * factor + i, y * factor + j);
            out.at(x, y) = s * inv;
        }
    return out;
}

std::vector<uint8_t> luminance_mask(const Film& ref, float max_luminance) {
    std::vector<uint8_t> m(ref.pixels.size());
    for (std::size_t i = 0; i < m.size(); ++i) m[i] = ref.pixels[i].luminance() <= max_luminance;
    return m;
}

std::vector<uint8_t> grow_exclusion(const std::vector<uint8_t>& mask, int width, int height,
                                    int margin) {
    std::vector<uint8_t> out = mask;
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            if (mask[std::size_t(y) * std::size_t(width) + std::size_t(x)]) continue;
            for (int dy = std::max(0, y - margin); dy <= std::min(height - 1, y + margin); ++dy)
                for (int dx = std::max(0, x - margin); dx <= std::min(width - 1, x + margin); ++dx)
                    out[std::size_t(dy) * std::size_t(width) + std::size_t(dx)] = 0;
        }
    return out;
}

double lowpass_rmse(const Film& a, const Film& b, const std::vector<uint8_t>& mask, int n) {
    if (a.width != b.width || a.height != b.height || mask.size() != a.pixels.size())
        throw std::invalid_argument("images differ in size");
    if (n < 1) throw std::invalid_argument("filter width below 1");
    const int w = a.width, h = a.height;
    // Summed-area tables of the difference and of the mask's holes: each window in O(1).
    const std::size_t stride = std::size_t(w) + 1;
    std::vector<double> sat(stride * std::size_t(h + 1) * 3, 0.0);
    std::vector<uint32_t> holes(stride * std::size_t(h + 1), 0);
    auto at = [&](int x, int y) { return std::size_t(y) * stride + std::size_t(x); };
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const std::size_t p = std::size_t(y) * std::size_t(w) + std::size_t(x);
            const RGB d = a.pixels[p] - b.pixels[p];
            const double dv[3] = {d.r, d.g, d.b};
            for (int c = 0; c < 3; ++c)
                sat[at(x + 1, y + 1) * 3 + c] = dv[c] + sat[at(x, y + 1) * 3 + c] +
                                                sat[at(x + 1, y) * 3 + c] - sat[at(x, y) * 3 + c];
            holes[at(x + 1, y + 1)] =
                uint32_t(!mask[p]) + holes[at(x, y + 1)] + holes[at(x + 1, y)] - holes[at(x, y)];
        }
    double se = 0.0;
    std::size_t windows = 0;
    const double inv = 1.0 / (double(n) * double(n));
    for (int y = 0; y + n <= h; ++y)
        for (int x = 0; x + n <= w; ++x) {
            if (holes[at(x + n, y + n)] + holes[at(x, y)] !=
                holes[at(x, y + n)] + holes[at(x + n, y)])
                continue;
            ++windows;
            for (int c = 0; c < 3; ++c) {
                const double m = (sat[at(x + n, y + n) * 3 + c] - sat[at(x, y + n) * 3 + c] -
                                  sat[at(x + n, y) * 3 + c] + sat[at(x, y) * 3 + c]) *
                                 inv;
                se += m * m;
            }
        }
    return windows ? std::sqrt(se / (3.0 * double(windows))) : 0.0;
}

}  // namespace foton
