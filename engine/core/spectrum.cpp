#include "spectrum.h"

#include <cmath>
#include <cstdint>
#include <cstring>

#include "cie_tables.h"
#include "rgb_spectrum.h"

namespace foton {

namespace {

// The sampling density's shape, sech^2(a (lambda - mu)), and its normalisation over the range.
constexpr float kBumpA = 0.0072f, kBumpMu = 538.f;
float bump_tanh(float lambda) {
    return std::tanh(kBumpA * (lambda - kBumpMu));
}

// Linear interpolation in a 5 nm table; zero outside it.
float table_at(const float* t, float lambda) {
    const float x = (lambda - cie::kLambdaMin) / cie::kStep;
    if (!(x >= 0.f) || x > float(cie::kSamples - 1)) return 0.f;
    const std::size_t i = std::min(std::size_t(x), cie::kSamples - 2);
    const float f = x - float(i);
    return t[i] * (1.f - f) + t[i + 1] * f;
}

// The integrals the film's estimate converges to, over the tables as interpolated above (a
// 0.05 nm midpoint rule: the interpolated products are piecewise quadratic).
struct Colorimetry {
    double d65_luminance = 0.0;  // integral of y-bar D65
    double to_srgb[3][3] = {};   // XYZ -> linear sRGB
    Colorimetry() {
        const int n = 9400;
        const double h = double(cie::kLambdaMax - cie::kLambdaMin) / n;
        double white[3] = {0.0, 0.0, 0.0};
        for (int i = 0; i < n; ++i) {
            const float l = float(cie::kLambdaMin + (i + 0.5) * h);
            const double e = table_at(cie::kD65, l) * h;
            white[0] += table_at(cie::kX, l) * e;
            white[1] += table_at(cie::kY, l) * e;
            white[2] += table_at(cie::kZ, l) * e;
        }
        d65_luminance = white[1];
        for (double& w : white) w /= d65_luminance;
        // RGB -> XYZ: the primaries' XYZ (luminance 1) as columns, each scaled so that RGB
        // (1, 1, 1) is the white; then inverted.
        const double px[3] = {0.64, 0.30, 0.15}, py[3] = {0.33, 0.60, 0.06};
        double p[3][3];
        for (int c = 0; c < 3; ++c) {
            p[0][c] = px[c] / py[c];
            p[1][c] = 1.0;
            p[2][c] = (1.0 - px[c] - py[c]) / py[c];
        }
        double pinv[3][3];
        invert(p, pinv);
        double s[3];
        for (int r = 0; r < 3; ++r)
            s[r] = pinv[r][0] * white[0] + pinv[r][1] * white[1] + pinv[r][2] * white[2];
        double m[3][3];
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c) m[r][c] = p[r][c] * s[c];
        invert(m, to_srgb);
    }
    static void invert(const double a[3][3], double out[3][3]) {
        const double det = a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
                           a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
                           a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c) {
                // The cofactor of a[c][r] over the determinant.
                const int r1 = (c + 1) % 3, r2 = (c + 2) % 3, c1 = (r + 1) % 3, c2 = (r + 2) % 3;
                out[r][c] = (a[r1][c1] * a[r2][c2] - a[r1][c2] * a[r2][c1]) / det;
            }
    }
};

const Colorimetry& colorimetry() {
    static const Colorimetry c;
    return c;
}

// The table's fit of rgb through a small direct-mapped cache per thread: a path meets the same
// few constant colours (a medium's coefficients, a sky, a material) over and over, and the
// table's interpolation costs more than the comparison.
SigmoidPolynomial fit_of(const RGB& rgb) {
    struct Entry {
        RGB rgb{-1.f};
        SigmoidPolynomial fit;
    };
    static thread_local Entry cache[64];
    uint32_t bits[3];
    std::memcpy(bits, &rgb, sizeof(bits));
    const uint32_t h = (bits[0] * 0x9e3779b1u) ^ (bits[1] * 0x85ebca77u) ^ (bits[2] * 0xc2b2ae3du);
    Entry& e = cache[h >> 26];
    if (!(e.rgb == rgb)) {
        e.rgb = rgb;
        e.fit = RgbSpectrumTable::get().reflectance(rgb);
    }
    return e.fit;
}

}  // namespace

float visible_wavelength_pdf(float lambda) {
    if (lambda < cie::kLambdaMin || lambda > cie::kLambdaMax) return 0.f;
    const float norm = kBumpA / (bump_tanh(cie::kLambdaMax) - bump_tanh(cie::kLambdaMin));
    const float c = std::cosh(kBumpA * (lambda - kBumpMu));
    return norm / (c * c);
}

float sample_visible_wavelength(float u) {
    // Inverts the CDF (tanh(a (lambda - mu)) - tanh(a (360 - mu))) / (its value at 830).
    const float t0 = bump_tanh(cie::kLambdaMin), t1 = bump_tanh(cie::kLambdaMax);
    const float l = kBumpMu + std::atanh(t0 + u * (t1 - t0)) / kBumpA;
    return std::clamp(l, cie::kLambdaMin, cie::kLambdaMax);
}

RGB cie_xyz(float lambda) {
    return {table_at(cie::kX, lambda), table_at(cie::kY, lambda), table_at(cie::kZ, lambda)};
}

float d65_normalised(float lambda) {
    return float(table_at(cie::kD65, lambda) / colorimetry().d65_luminance);
}

RGB xyz_to_linear_srgb(const RGB& xyz) {
    const auto& m = colorimetry().to_srgb;
    auto row = [&](int r) { return float(m[r][0] * xyz.r + m[r][1] * xyz.g + m[r][2] * xyz.b); };
    return {row(0), row(1), row(2)};
}

Wavelengths Wavelengths::sample(float u) {
    Wavelengths w;
    for (int i = 0; i < 3; ++i) {
        float ui = u + float(i) * (1.f / 3.f);
        if (ui >= 1.f) ui -= 1.f;
        w.lambda[i] = sample_visible_wavelength(ui);
        w.pdf[i] = visible_wavelength_pdf(w.lambda[i]);
        w.d65[i] = d65_normalised(w.lambda[i]);
    }
    return w;
}

RGB Wavelengths::to_rgb(const RGB& values) const {
    const float v[3] = {values.r, values.g, values.b};
    RGB xyz{0.f};
    for (int i = 0; i < 3; ++i)
        if (pdf[i] > 0.f && v[i] != 0.f) xyz += cie_xyz(lambda[i]) * (v[i] / (3.f * pdf[i]));
    return xyz_to_linear_srgb(xyz);
}

RGB Wavelengths::reflectance(const RGB& rgb) const {
    if (rgb.r == rgb.g && rgb.g == rgb.b) return rgb;  // a grey is a constant spectrum
    if (rgb.max_component() > 1.f) return unbounded(rgb);
    const SigmoidPolynomial s = fit_of(rgb);
    return {s(lambda[0]), s(lambda[1]), s(lambda[2])};
}

RGB Wavelengths::unbounded(const RGB& rgb) const {
    if (rgb.r == rgb.g && rgb.g == rgb.b) return rgb;
    const float m = rgb.max_component();
    if (!(m > 0.f)) return RGB{0.f};
    const SigmoidPolynomial s = fit_of(rgb * (0.5f / m));
    return RGB{s(lambda[0]), s(lambda[1]), s(lambda[2])} * (2.f * m);
}

RGB Wavelengths::illuminant(const RGB& rgb) const {
    const RGB u = unbounded(rgb);
    return {u.r * d65[0], u.g * d65[1], u.b * d65[2]};
}

}  // namespace foton
