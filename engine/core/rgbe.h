#pragma once
// Ward's shared-exponent colour ("Real Pixels", Graphics Gems II, 1991): three 8-bit mantissas
// and one exponent byte, 4 bytes for an RGB of floats. The photon-mapping thesis (6.5) stores
// precomputed irradiance so, and Jensen's photon maps the photons' power: a map of millions of
// photons keeps 8 of its bytes per photon. The largest channel keeps 8 significant bits
// (relative error below 2^-8); a smaller one has the same absolute error, and one below a
// step (at most 1/128 of the largest) is dark. Negative and NaN channels encode as 0.
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "rgb.h"

namespace foton {

inline uint32_t encode_rgbe(const RGB& c) {
    const float r = c.r > 0.f ? c.r : 0.f, g = c.g > 0.f ? c.g : 0.f, b = c.b > 0.f ? c.b : 0.f;
    const float v = std::max(r, std::max(g, b));
    if (!(v >= 1e-32f)) return 0;
    int e = 0;
    // v = m 2^e with m in [0.5, 1): the mantissas are channel / 2^e * 256, the largest in
    // [128, 256). Beyond the exponent byte's range the colour saturates.
    const float m = std::frexp(v, &e);
    if (e > 127) return 0xffffffu | (255u << 24);
    const float scale = m * 256.f / v;
    auto byte = [&](float x) { return uint32_t(std::min(255.f, x * scale)); };
    return byte(r) | byte(g) << 8 | byte(b) << 16 | uint32_t(e + 128) << 24;
}

// The centre of each mantissa's interval (unbiased for a uniformly distributed remainder),
// but 0 for a zero mantissa: a channel with no light (a red light's green) stays dark instead
// of getting half a step of its largest channel.
inline RGB decode_rgbe(uint32_t v) {
    const uint32_t e = v >> 24;
    if (e == 0) return RGB{0.f};
    const float f = std::ldexp(1.f, int(e) - (128 + 8));
    auto channel = [&](uint32_t m) { return m ? (float(m) + 0.5f) * f : 0.f; };
    return {channel(v & 255u), channel(v >> 8 & 255u), channel(v >> 16 & 255u)};
}

}  // namespace foton
