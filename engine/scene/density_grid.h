#pragma once
// A medium's density on a regular grid (pbrt-v4's `uniformgrid`): a SampledGrid of floats
// (sampled_grid.h: samples at cell centres, trilinear, fading to zero over the half cell at the
// box's faces). The medium's coefficients are multiplied by it.
//
// The majorant grid bounds it from above on a coarse grid of at most 16^3 cells over the same
// box (pbrt-v4's MajorantGrid): each cell holds the largest sample that can influence a point
// in it, so delta and ratio tracking may take it as the majorant across the cell.
#include <cstdint>
#include <vector>

#include "engine/core/math.h"
#include "kernels/grid_dda.h"
#include "sampled_grid.h"

namespace foton {

// A density (or any non-negative scalar) on a SampledGrid, with its majorant grid.
class DensityGrid : public SampledGrid<float> {
  public:
    // `values` has nx * ny * nz finite, non-negative entries; `box` is not empty.
    DensityGrid(int nx, int ny, int nz, std::vector<float> values, const Bounds3& box);

    float max_value() const { return max_; }

    // The majorant grid: its frame over the box and each cell's bound on the density.
    const kern::GridFrame& majorant_frame() const { return frame_; }
    float majorant(uint32_t cell) const { return majorant_[cell]; }
    const float* majorant_data() const { return majorant_.data(); }

  private:
    float max_ = 0.f;
    kern::GridFrame frame_;
    std::vector<float> majorant_;
};

}  // namespace foton
