#pragma once
// Piecewise-constant densities sampled by inverting their CDFs: the environment map's
// importance sampling (Distribution2D over its texels) and the final-gather guide's
// histogram share the inversion.
#include <cstdint>
#include <vector>

#include "math.h"
#include "sampler.h"

namespace foton {

// Index of u's interval in a CDF of n + 1 entries (cdf[0] = 0, cdf[n] = 1), skipping
// intervals of zero width, and u's position within it in [0, 1).
int invert_cdf(const float* cdf, int n, float u, float& within);

// A density on [0, 1)^2 that is constant on each of nu x nv cells, proportional to the
// given non-negative weights (row-major: weights[row * nu + column], rows along v).
// Sampling picks a row by its marginal with u.x and a cell of the row with u.y, so
// stratified u stay stratified.
class Distribution2D {
  public:
    Distribution2D() = default;
    // Throws std::invalid_argument when the weights are all zero or not finite.
    Distribution2D(const std::vector<float>& weights, int nu, int nv);

    bool empty() const { return nu_ == 0; }
    int nu() const { return nu_; }
    int nv() const { return nv_; }
    // A point of [0, 1)^2 and its density there (with respect to area on the square).
    Point2 sample(Point2 u, float& pdf) const;
    float pdf(Point2 p) const;
    // The weights' sum over the cells times a cell's area: the integral of the
    // piecewise-constant function the weights describe.
    double integral() const { return integral_; }

  private:
    int nu_ = 0, nv_ = 0;
    std::vector<float> density_;   // per cell, integrates to 1 over the square
    std::vector<float> row_cdf_;   // nv + 1
    std::vector<float> cell_cdf_;  // per row, nu + 1
    double integral_ = 0.0;
};

}  // namespace foton
