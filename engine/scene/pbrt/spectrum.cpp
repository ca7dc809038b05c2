#include "spectrum.h"

#include <algorithm>
#include <cmath>

#include "cie_1931.h"
#include "engine/scene/metals.h"

namespace foton::pbrt {

namespace {

struct Xyz {
    double x = 0, y = 0, z = 0;
};

// The CIE 1931 2-degree observer at l nm, linear between the 5 nm table's samples.
Xyz cmf(double l) {
    const double x = (l - kCieFirstNm) / kCieStepNm;
    if (!(x >= 0.0 && x <= double(kCieSamples - 1))) return {};
    const int i = std::min(int(x), kCieSamples - 2);
    const double f = x - double(i);
    auto at = [&](const float* t) { return double(t[i]) * (1.0 - f) + double(t[i + 1]) * f; };
    return {at(kCieX), at(kCieY), at(kCieZ)};
}

RGB xyz_to_srgb(const Xyz& c) {
    return {float(3.2404542 * c.x - 1.5371385 * c.y - 0.4985314 * c.z),
            float(-0.9692660 * c.x + 1.8760108 * c.y + 0.0415560 * c.z),
            float(0.0556434 * c.x - 0.2040259 * c.y + 1.0572252 * c.z)};
}

template <class F>
Xyz integrate(F spectrum) {
    Xyz s;
    for (double l = 360.0; l <= 830.0; l += 1.0) {
        const double v = spectrum(l);
        const Xyz c = cmf(l);
        s.x += v * c.x;
        s.y += v * c.y;
        s.z += v * c.z;
    }
    return s;
}

RGB clamp_positive(RGB c) {
    return {std::max(c.r, 0.f), std::max(c.g, 0.f), std::max(c.b, 0.f)};
}

RGB chromaticity_rgb(double x, double y) {
    return xyz_to_srgb({x / y, 1.0, (1.0 - x - y) / y});
}

struct Named {
    const char* name;
    RGB rgb;
};

// Metals: complex index at about 650, 550 and 450 nm. Glasses: the index at the helium d
// line (587.6 nm), where their catalogues quote it.
const Named kNamed[] = {
    {"metal-Au-eta", {0.143f, 0.374f, 1.442f}},
    {"metal-Au-k", {3.983f, 2.385f, 1.603f}},
    {"metal-Ag-eta", {0.155f, 0.117f, 0.138f}},
    {"metal-Ag-k", {4.828f, 3.122f, 2.147f}},
    {"metal-Cu-eta", {0.200f, 0.924f, 1.102f}},
    {"metal-Cu-k", {3.912f, 2.452f, 2.142f}},
    {"metal-Al-eta", {1.657f, 0.880f, 0.521f}},
    {"metal-Al-k", {9.224f, 6.270f, 4.837f}},
    {"metal-CuZn-eta", {0.444f, 0.527f, 1.094f}},
    {"metal-CuZn-k", {3.695f, 2.765f, 1.829f}},
    {"glass-BK7", RGB{1.5168f}},
    {"glass-BAF10", RGB{1.6700f}},
    {"glass-FK51A", RGB{1.4866f}},
    {"glass-LASF9", RGB{1.8503f}},
    {"glass-F5", RGB{1.6034f}},
};

// Planck's law: a blackbody's spectral radiance at nm nanometres and `kelvin`.
double planck(double nm, double kelvin) {
    const double l = nm * 1e-9;
    const double h = 6.62606957e-34, k = 1.3806488e-23, cc = 299792458.0;
    return (2.0 * h * cc * cc) / (std::pow(l, 5) * (std::exp(h * cc / (l * k * kelvin)) - 1.0));
}

}  // namespace

RGB blackbody_rgb(float kelvin) {
    const Xyz c = integrate([kelvin](double nm) { return planck(nm, kelvin); });
    return clamp_positive(xyz_to_srgb({c.x / c.y, 1.0, c.z / c.y}));
}

RGB blackbody_emission_rgb(float kelvin) {
    // Wien's displacement law gives the peak pbrt-v4 divides by.
    const double peak = planck(2.8977721e-3 / double(kelvin) * 1e9, kelvin);
    const Xyz c = integrate([&](double nm) { return planck(nm, kelvin) / peak; });
    return clamp_positive(xyz_to_srgb(c));
}

RGB sampled_spectrum_rgb(const std::vector<float>& pairs, bool illuminant) {
    auto at = [&](double l) {
        const std::size_t n = pairs.size() / 2;
        if (l <= pairs[0]) return double(pairs[1]);
        if (l >= pairs[2 * (n - 1)]) return double(pairs[2 * n - 1]);
        for (std::size_t i = 0; i + 1 < n; ++i) {
            const double l0 = pairs[2 * i], l1 = pairs[2 * i + 2];
            if (l <= l1) {
                const double t = l1 > l0 ? (l - l0) / (l1 - l0) : 0.0;
                return pairs[2 * i + 1] * (1.0 - t) + pairs[2 * i + 3] * t;
            }
        }
        return double(pairs[2 * n - 1]);
    };
    const Xyz c = integrate(at);
    if (illuminant) {
        if (c.y <= 0.0) return RGB{0.f};
        return clamp_positive(xyz_to_srgb({c.x / c.y, 1.0, c.z / c.y}));
    }
    // A reflectance seen under equal energy, balanced so that a flat spectrum stays grey.
    const Xyz w = integrate([](double) { return 1.0; });
    const RGB rgb = xyz_to_srgb({c.x / w.y, c.y / w.y, c.z / w.y});
    const RGB white = xyz_to_srgb({w.x / w.y, 1.0, w.z / w.y});
    return clamp_positive({rgb.r / white.r, rgb.g / white.g, rgb.b / white.b});
}

std::optional<RGB> named_spectrum_rgb(const std::string& name) {
    for (const Metal& m : metals()) {
        const std::string stem = std::string("metal-") + m.symbol;
        if (name == stem + "-eta") return m.eta;
        if (name == stem + "-k") return m.k;
    }
    for (const Named& n : kNamed)
        if (name == n.name) return n.rgb;
    if (name == "stdillum-D65") return RGB{1.f};
    if (name == "stdillum-D50") return clamp_positive(chromaticity_rgb(0.34567, 0.35850));
    if (name == "stdillum-A") return clamp_positive(chromaticity_rgb(0.44757, 0.40745));
    return std::nullopt;
}

std::string named_spectrum_list() {
    std::string s;
    for (const Metal& m : metals()) s += std::string("metal-") + m.symbol + "-eta, -k, ";
    for (const Named& n : kNamed) s += std::string(n.name) + ", ";
    return s + "stdillum-D65, stdillum-D50, stdillum-A";
}

}  // namespace foton::pbrt
