#pragma once
// A 2D density that is bilinear between the nodes of a regular grid over [0, 1]^2, with the
// warp that samples it and the inverse of that warp, optionally conditioned on parameters: the
// grid is stored for every combination of parameter nodes and interpolated multilinearly
// between them. This is the structure of the measured materials of the RGL database (Dupuy and
// Jakob 2018: the visible-normal and luminance warps of a `.bsdf` file, and its spectra as a
// plain interpolant); rows (y) are sampled first by the marginal, then the column within the
// row pair by the conditional, each solving the linear density of its interval exactly, as
// pbrt-v4's and Mitsuba's versions do, so the files' data mean the same here.
#include <cstdint>
#include <vector>

#include "sampler.h"

namespace foton {

class Warp2D {
  public:
    struct Result {
        Point2 p;         // the warped point (sample) or the sample that warps to p (invert)
        float pdf = 0.f;  // the density at the warped point
    };

    Warp2D() = default;
    // `data`: one width x height grid (x fastest) per combination of parameter nodes, the last
    // parameter fastest; `params[d]`: parameter d's node values, increasing. `normalize`: each
    // grid rescaled to integrate to 1 (needed for sampling; `build_cdf` implies it).
    Warp2D(const float* data, int width, int height, std::vector<std::vector<float>> params,
           bool normalize = true, bool build_cdf = true);

    int params() const { return int(param_values_.size()); }
    // u in [0, 1)^2 to a point with the density at it; `param` holds params() values.
    Result sample(Point2 u, const float* param = nullptr) const;
    // The sample u that sample() maps to p, and the density at p.
    Result invert(Point2 p, const float* param = nullptr) const;
    // The density (or, unnormalised, the interpolated data) at p.
    float eval(Point2 p, const float* param = nullptr) const;

  private:
    // The parameter interval each parameter falls in: the first grid's offset (in grids) and
    // the interpolation weights of the 2^d corners.
    struct Corners {
        uint32_t slice = 0;
        float weight[2 * 4] = {};
    };
    Corners corners(const float* param) const;
    // The grid cell holding p: its first node's offset (slice included), where p lies in it,
    // and the density along its two x edges at that y (c0 at x = 0, c1 at x = 1).
    struct Cell {
        uint32_t col, row, offset;
        float fx, fy, c0, c1;
    };
    Cell cell_at(Point2 p, const Corners& c) const;
    // The density along the x edges of the cell whose first node is `offset`, at fy.
    void edges(uint32_t offset, float fy, const Corners& c, float& c0, float& c1) const;
    // values[offset + i] interpolated over the parameter corners (grids `stride` apart).
    float lookup(const std::vector<float>& values, uint32_t offset, uint32_t stride,
                 const Corners& c) const;

    int width_ = 0, height_ = 0;
    std::vector<std::vector<float>> param_values_;
    std::vector<uint32_t> param_stride_;  // in grids; 0 for a parameter of one node
    std::vector<float> data_, marginal_cdf_, conditional_cdf_;
};

}  // namespace foton
