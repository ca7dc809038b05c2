#include "ssim.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace foton {

namespace {

constexpr double kC1 = 0.01 * 0.01, kC2 = 0.03 * 0.03;  // (K1 L)^2, (K2 L)^2 with L = 1

std::vector<double> display_luminance(const Film& f, float exposure, float gamma) {
    std::vector<double> y(f.pixels.size());
    for (std::size_t i = 0; i < y.size(); ++i) {
        const RGB& c = f.pixels[i];
        const double v = exposure * (0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b);
        // NaN fails both comparisons and becomes 0.
        const double clamped = v > 0.0 ? std::min(v, 1.0) : 0.0;
        y[i] = std::pow(clamped, 1.0 / gamma);
    }
    return y;
}

// The window's weights: a Gaussian of sigma 1.5 over 2r + 1 taps, summing to 1.
std::vector<double> gaussian_taps(int r) {
    std::vector<double> w(std::size_t(2 * r + 1));
    double sum = 0.0;
    for (int i = -r; i <= r; ++i) sum += w[std::size_t(i + r)] = std::exp(-i * i / (2 * 1.5 * 1.5));
    for (double& v : w) v /= sum;
    return w;
}

// Gaussian-weighted window sums of `v` at every centre whose window lies in the image:
// (w - 2r) x (h - 2r) values, separably (rows, then columns).
std::vector<double> blur(const std::vector<double>& v, int w, int h,
                         const std::vector<double>& taps, int r) {
    const int ow = w - 2 * r, oh = h - 2 * r;
    std::vector<double> rows(std::size_t(ow) * std::size_t(h));
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < ow; ++x) {
            double s = 0.0;
            for (int k = 0; k <= 2 * r; ++k)
                s += taps[std::size_t(k)] * v[std::size_t(y) * w + x + k];
            rows[std::size_t(y) * ow + x] = s;
        }
    std::vector<double> out(std::size_t(ow) * std::size_t(oh));
    for (int y = 0; y < oh; ++y)
        for (int x = 0; x < ow; ++x) {
            double s = 0.0;
            for (int k = 0; k <= 2 * r; ++k)
                s += taps[std::size_t(k)] * rows[std::size_t(y + k) * ow + x];
            out[std::size_t(y) * ow + x] = s;
        }
    return out;
}

}  // namespace

double ssim(const Film& a, const Film& b, const std::vector<uint8_t>* mask, float exposure,
            float gamma) {
    if (a.width != b.width || a.height != b.height)
        throw std::invalid_argument("ssim: the images differ in size");
    if (mask && mask->size() != a.pixels.size())
        throw std::invalid_argument("ssim: the mask differs in size from the images");
    const int w = a.width, h = a.height;
    if (w <= 0 || h <= 0) return std::numeric_limits<double>::quiet_NaN();
    const int r = std::min(5, (std::min(w, h) - 1) / 2);
    const std::vector<double> x = display_luminance(a, exposure, gamma);
    const std::vector<double> y = display_luminance(b, exposure, gamma);
    std::vector<double> xx(x.size()), yy(x.size()), xy(x.size());
    for (std::size_t i = 0; i < x.size(); ++i) {
        xx[i] = x[i] * x[i];
        yy[i] = y[i] * y[i];
        xy[i] = x[i] * y[i];
    }
    const std::vector<double> taps = gaussian_taps(r);
    const std::vector<double> mx = blur(x, w, h, taps, r), my = blur(y, w, h, taps, r);
    const std::vector<double> mxx = blur(xx, w, h, taps, r), myy = blur(yy, w, h, taps, r);
    const std::vector<double> mxy = blur(xy, w, h, taps, r);
    const int ow = w - 2 * r, oh = h - 2 * r;
    double sum = 0.0;
    std::size_t n = 0;
    for (int cy = 0; cy < oh; ++cy)
        for (int cx = 0; cx < ow; ++cx) {
            if (mask && !(*mask)[std::size_t(cy + r) * w + cx + r]) continue;
            const std::size_t i = std::size_t(cy) * ow + cx;
            const double vx = mxx[i] - mx[i] * mx[i], vy = myy[i] - my[i] * my[i];
            const double cov = mxy[i] - mx[i] * my[i];
            sum += (2.0 * mx[i] * my[i] + kC1) * (2.0 * cov + kC2) /
                   ((mx[i] * mx[i] + my[i] * my[i] + kC1) * (vx + vy + kC2));
            ++n;
        }
    return n ? sum / double(n) : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace foton
