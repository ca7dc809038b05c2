#pragma once
// RGB to spectrum by Jakob and Hanika's sigmoid polynomials (2019): a reflectance is
// s(lambda) = 1/2 + x / (2 sqrt(1 + x^2)) with x = c0 t^2 + c1 t + c2 a quadratic in the
// normalised wavelength t = (lambda - 360) / 470, bounded in [0, 1], smooth, and fitted so that
// its colour under D65 is the RGB. The fit is Newton's method on the three coefficients (our
// own, residual in linear sRGB); a table over RGB space (the largest channel and the other two's
// ratios to it, as in the paper) holds fits to interpolate, built once on first use. An
// unbounded quantity is 2 max(rgb) times the reflectance fitted to rgb / (2 max(rgb)).
#include <array>
#include <vector>

#include "rgb.h"

namespace foton {

struct SigmoidPolynomial {
    float c0 = 0.f, c1 = 0.f, c2 = 0.f;
    float operator()(float lambda) const;
};

// The reflectance of sRGB colour rgb (channels in [0, 1]) fitted from `start` (Newton with a
// backtracking line search); `residual` gets the largest channel error left. Channels at 0 or 1
// are reached only in the limit: the fit stops close to them.
SigmoidPolynomial fit_sigmoid_polynomial(const RGB& rgb, SigmoidPolynomial start = {},
                                         float* residual = nullptr);

// The table of fits (built on first use, in parallel; about 100 k fits).
class RgbSpectrumTable {
  public:
    static constexpr int kRes = 32;
    static const RgbSpectrumTable& get();
    // The reflectance of rgb (channels in [0, 1]): exact for greys, else interpolated.
    SigmoidPolynomial reflectance(const RGB& rgb) const;

  private:
    RgbSpectrumTable();
    std::array<float, kRes> z_nodes_{};
    // [largest channel][z][y][x] -> three coefficients.
    std::vector<float> coeffs_;
    static std::size_t index(int channel, int zi, int yi, int xi) {
        return ((std::size_t(channel) * kRes + std::size_t(zi)) * kRes + std::size_t(yi)) * kRes *
                   3 +
               std::size_t(xi) * 3;
    }
    const float* at(int channel, int zi, int yi, int xi) const {
        return &coeffs_[index(channel, zi, yi, xi)];
    }
};

}  // namespace foton
