#pragma once
// Directions binned as the cells of a cube map: face f (axis f / 2, positive for even f), each
// face's [-1, 1]^2 cut into res x res cells. The projection maps of environment, point and
// spot lights keep one entry per bin.
#include <algorithm>
#include <cmath>
#include <cstddef>

#include "engine/core/math.h"

namespace foton {

// The direction of cube face f at face coordinates (u, v) in [-1, 1]^2, not normalised.
inline Vec3 face_direction(int f, float u, float v) {
    const int a = f / 2;
    Vec3 d;
    d[a] = f % 2 == 0 ? 1.f : -1.f;
    d[(a + 1) % 3] = u;
    d[(a + 2) % 3] = v;
    return d;
}

struct CubeBin {
    int face = 0;
    float u = 0.f, v = 0.f;  // the direction's face coordinates
    std::size_t index = 0;   // (face * res + j) * res + i
};

// The bin of direction d (need not be unit).
inline CubeBin cube_bin(const Vec3& d, int res) {
    const float ax = std::fabs(d.x), ay = std::fabs(d.y), az = std::fabs(d.z);
    const int a = ax >= ay && ax >= az ? 0 : ay >= az ? 1 : 2;
    const float major = std::fabs(d[a]);
    CubeBin b;
    b.face = 2 * a + (d[a] >= 0.f ? 0 : 1);
    b.u = d[(a + 1) % 3] / major;
    b.v = d[(a + 2) % 3] / major;
    auto cell = [&](float c) {
        return std::clamp(int(std::floor((c + 1.f) * 0.5f * float(res))), 0, res - 1);
    };
    b.index = (std::size_t(b.face) * std::size_t(res) + std::size_t(cell(b.v))) * std::size_t(res) +
              std::size_t(cell(b.u));
    return b;
}

}  // namespace foton
