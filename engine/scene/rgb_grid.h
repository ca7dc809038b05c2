#pragma once
// An RGB quantity on a regular grid (pbrt-v4's `rgbgrid` medium: its sigma_a, sigma_s and Le):
// nx x ny x nz RGB samples at the cell centres of an axis-aligned box, x fastest, trilinear
// between them and zero outside, exactly as DensityGrid does for one channel.
#include <vector>

#include "engine/core/math.h"
#include "engine/core/rgb.h"

namespace foton {

class RGBGrid {
  public:
    // `values` has nx * ny * nz finite, non-negative entries; `box` is not empty.
    RGBGrid(int nx, int ny, int nz, std::vector<RGB> values, const Bounds3& box);

    const Bounds3& box() const { return box_; }
    int nx() const { return n_[0]; }
    int ny() const { return n_[1]; }
    int nz() const { return n_[2]; }
    RGB lookup(const Vec3& p) const;
    RGB sample(int x, int y, int z) const {
        if (x < 0 || y < 0 || z < 0 || x >= n_[0] || y >= n_[1] || z >= n_[2]) return RGB{0.f};
        return values_[(std::size_t(z) * std::size_t(n_[1]) + std::size_t(y)) * std::size_t(n_[0]) +
                       std::size_t(x)];
    }

  private:
    int n_[3];
    std::vector<RGB> values_;
    Bounds3 box_;
};

}  // namespace foton
