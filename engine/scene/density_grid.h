#pragma once
// A medium's density on a regular grid (pbrt-v4's `uniformgrid`): nx x ny x nz samples at the
// centres of the cells of an axis-aligned box, x fastest, interpolated trilinearly and zero
// outside the samples (so the density fades out over the half cell at the box's faces, as
// pbrt-v4's SampledGrid does). The medium's coefficients are multiplied by it.
//
// The majorant grid bounds it from above on a coarse grid of at most 16^3 cells over the same
// box (pbrt-v4's MajorantGrid): each cell holds the largest sample that can influence a point
// in it, so delta and ratio tracking may take it as the majorant across the cell.
#include <cstdint>
#include <vector>

#include "engine/core/math.h"
#include "kernels/grid_dda.h"

namespace foton {

// Where world point p falls among the nx x ny x nz samples at the cell centres of `box`: the
// lower corner sample i and the fractions f towards the next, for trilinear interpolation
// (samples outside the grid count as zero). False when p is outside the box.
bool grid_position(const Bounds3& box, const int n[3], const Vec3& p, int i[3], float f[3]);

class DensityGrid {
  public:
    // `values` has nx * ny * nz finite, non-negative entries; `box` is not empty.
    DensityGrid(int nx, int ny, int nz, std::vector<float> values, const Bounds3& box);

    const Bounds3& box() const { return box_; }
    int nx() const { return n_[0]; }
    int ny() const { return n_[1]; }
    int nz() const { return n_[2]; }
    float max_value() const { return max_; }
    // The density at world point p (0 outside the box).
    float lookup(const Vec3& p) const;
    // The sample at integer coordinates (0 outside).
    float sample(int x, int y, int z) const {
        if (x < 0 || y < 0 || z < 0 || x >= n_[0] || y >= n_[1] || z >= n_[2]) return 0.f;
        return values_[(std::size_t(z) * std::size_t(n_[1]) + std::size_t(y)) * std::size_t(n_[0]) +
                       std::size_t(x)];
    }

    // The majorant grid: its frame over the box and each cell's bound on the density.
    const kern::GridFrame& majorant_frame() const { return frame_; }
    float majorant(uint32_t cell) const { return majorant_[cell]; }
    const float* majorant_data() const { return majorant_.data(); }

  private:
    int n_[3];
    std::vector<float> values_;
    Bounds3 box_;
    float max_ = 0.f;
    kern::GridFrame frame_;
    std::vector<float> majorant_;
};

}  // namespace foton
