#pragma once
// Plain single-ray and hit records shared by the kernels. No engine types here on purpose:
// kernels depend on nothing but xsimd.
#include <cstdint>
#include <limits>

namespace foton::kern {

inline constexpr uint32_t kInvalidId = 0xffffffffu;
inline constexpr float kInf = std::numeric_limits<float>::infinity();

struct Ray1 {
    float ox, oy, oz;
    float dx, dy, dz;
    float tmin, tmax;
};

// Closest hit so far. `t` doubles as the current upper bound of the search.
struct TriHit {
    float t = kInf;
    float u = 0.f, v = 0.f;
    uint32_t id = kInvalidId;
    bool valid() const { return id != kInvalidId; }
};

}  // namespace foton::kern
