#pragma once
// A quantity on a regular grid (pbrt-v4's SampledGrid): nx x ny x nz samples at the centres of
// the cells of an axis-aligned box, x fastest, interpolated trilinearly and zero outside the
// samples (so the quantity fades out over the half cell at the box's faces). T is float (a
// density, a temperature: density_grid.h) or RGB (an rgbgrid medium's coefficients and Le).
#include <cmath>
#include <vector>

#include "engine/core/math.h"
#include "engine/core/rgb.h"

namespace foton {

template <class T>
class SampledGrid {
  public:
    // `values` has nx * ny * nz finite, non-negative entries; `box` is not empty.
    SampledGrid(int nx, int ny, int nz, std::vector<T> values, const Bounds3& box)
        : n_{nx, ny, nz}, values_(std::move(values)), box_(box) {}

    const Bounds3& box() const { return box_; }
    int nx() const { return n_[0]; }
    int ny() const { return n_[1]; }
    int nz() const { return n_[2]; }
    // The sample at integer coordinates (0 outside).
    T sample(int x, int y, int z) const {
        if (x < 0 || y < 0 || z < 0 || x >= n_[0] || y >= n_[1] || z >= n_[2]) return T(0.f);
        return values_[(std::size_t(z) * std::size_t(n_[1]) + std::size_t(y)) * std::size_t(n_[0]) +
                       std::size_t(x)];
    }
    // The value at world point p (0 outside the box).
    T lookup(const Vec3& p) const {
        const Vec3 e = box_.diagonal();
        const float u[3] = {(p.x - box_.lo.x) / e.x * float(n_[0]) - 0.5f,
                            (p.y - box_.lo.y) / e.y * float(n_[1]) - 0.5f,
                            (p.z - box_.lo.z) / e.z * float(n_[2]) - 0.5f};
        int i[3];
        float f[3];
        for (int a = 0; a < 3; ++a) {
            // The box is [-0.5, n - 0.5] in sample coordinates; nothing outside it.
            if (!(u[a] >= -0.5f && u[a] <= float(n_[a]) - 0.5f)) return T(0.f);
            const float fl = std::floor(u[a]);
            i[a] = int(fl);
            f[a] = u[a] - fl;
        }
        auto lerp = [](float t, const T& a, const T& b) { return a + (b - a) * t; };
        const T c00 = lerp(f[0], sample(i[0], i[1], i[2]), sample(i[0] + 1, i[1], i[2]));
        const T c10 = lerp(f[0], sample(i[0], i[1] + 1, i[2]), sample(i[0] + 1, i[1] + 1, i[2]));
        const T c01 = lerp(f[0], sample(i[0], i[1], i[2] + 1), sample(i[0] + 1, i[1], i[2] + 1));
        const T c11 =
            lerp(f[0], sample(i[0], i[1] + 1, i[2] + 1), sample(i[0] + 1, i[1] + 1, i[2] + 1));
        return lerp(f[2], lerp(f[1], c00, c10), lerp(f[1], c01, c11));
    }

  protected:
    const std::vector<T>& values() const { return values_; }

  private:
    int n_[3];
    std::vector<T> values_;
    Bounds3 box_;
};

using RGBGrid = SampledGrid<RGB>;

}  // namespace foton
