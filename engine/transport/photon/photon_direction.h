#pragma once
// The photon map's two-byte directions (Jensen): theta and phi quantised to 256 steps each,
// for the photons' incident directions and normals and the precomputed points' normals.
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "engine/core/math.h"

namespace foton {

// Jensen's two-byte direction: theta and phi quantised to 256 steps each.
inline uint16_t encode_direction(const Vec3& w) {
    const float theta = std::acos(std::clamp(w.z, -1.f, 1.f));
    float phi = std::atan2(w.y, w.x);
    if (phi < 0.f) phi += 2.f * kPi;
    const uint16_t t = uint16_t(std::min(255.f, theta * (256.f / kPi)));
    const uint16_t f = uint16_t(std::min(255.f, phi * (256.f / (2.f * kPi))));
    return uint16_t(t << 8 | f);
}

// Decoding runs for every photon of every estimate (radiance, SPPM gathering, shadow-photon
// tests), so it reads Jensen's tables of the 256 bin centres' sines and cosines.
struct DirectionTables {
    float sin_theta[256], cos_theta[256], sin_phi[256], cos_phi[256];
    DirectionTables() {
        for (int i = 0; i < 256; ++i) {
            const float theta = (float(i) + 0.5f) * (kPi / 256.f);
            const float phi = (float(i) + 0.5f) * (2.f * kPi / 256.f);
            sin_theta[i] = std::sin(theta);
            cos_theta[i] = std::cos(theta);
            sin_phi[i] = std::sin(phi);
            cos_phi[i] = std::cos(phi);
        }
    }
};
inline const DirectionTables kDirections;

inline Vec3 decode_direction(uint16_t d) {
    const int t = d >> 8, f = d & 255;
    const float st = kDirections.sin_theta[t];
    return {st * kDirections.cos_phi[f], st * kDirections.sin_phi[f], kDirections.cos_theta[t]};
}

}  // namespace foton
