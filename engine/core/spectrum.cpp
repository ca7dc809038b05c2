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
