#include "metals.h"

#include <algorithm>
#include <cmath>

namespace foton {

std::span<const Metal> metals() {
    static constexpr Metal kMetals[] = {
        {"gold", "Au", {0.143f, 0.374f, 1.442f}, {3.983f, 2.385f, 1.603f}},
        {"silver", "Ag", {0.155f, 0.117f, 0.138f}, {4.828f, 3.122f, 2.147f}},
        {"copper", "Cu", {0.200f, 0.924f, 1.102f}, {3.912f, 2.452f, 2.142f}},
        {"aluminium", "Al", {1.657f, 0.880f, 0.521f}, {9.224f, 6.270f, 4.837f}},
        {"brass", "CuZn", {0.444f, 0.527f, 1.094f}, {3.695f, 2.765f, 1.829f}},
    };
    return kMetals;
}

Fresnel conductor_from_reflectance(const RGB& r) {
    auto k = [](float v) {
        v = std::min(v, 0.9999f);
        return 2.f * std::sqrt(v / (1.f - v));
    };
    Fresnel f;
    f.kind = FresnelKind::Conductor;
    f.eta = RGB{1.f};
    f.k = {k(r.r), k(r.g), k(r.b)};
    return f;
}

}  // namespace foton
