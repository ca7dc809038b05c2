#include "rgb_grid.h"

#include "density_grid.h"

namespace foton {

RGBGrid::RGBGrid(int nx, int ny, int nz, std::vector<RGB> values, const Bounds3& box)
    : n_{nx, ny, nz}, values_(std::move(values)), box_(box) {}

RGB RGBGrid::lookup(const Vec3& p) const {
    int i[3];
    float f[3];
    if (!grid_position(box_, n_, p, i, f)) return RGB{0.f};
    auto lerp = [](float t, const RGB& a, const RGB& b) { return a + (b - a) * t; };
    const RGB c00 = lerp(f[0], sample(i[0], i[1], i[2]), sample(i[0] + 1, i[1], i[2]));
    const RGB c10 = lerp(f[0], sample(i[0], i[1] + 1, i[2]), sample(i[0] + 1, i[1] + 1, i[2]));
    const RGB c01 = lerp(f[0], sample(i[0], i[1], i[2] + 1), sample(i[0] + 1, i[1], i[2] + 1));
    const RGB c11 =
        lerp(f[0], sample(i[0], i[1] + 1, i[2] + 1), sample(i[0] + 1, i[1] + 1, i[2] + 1));
    return lerp(f[2], lerp(f[1], c00, c10), lerp(f[1], c01, c11));
}

}  // namespace foton
