#pragma once
// A piecewise-constant density on [0, 1)^2 (nu x nv cells, like Distribution2D) that can be
// sampled within any axis-aligned window of the square: a portal environment light samples
// only the directions through its portal as seen from the shading point, which in its
// rectified map is a rectangle that changes from point to point. A summed-area table gives
// the window's integral in O(1); the row is found by bisection on it, the column within the
// row by bisection on the row's running sums.
#include <vector>

#include "math.h"
#include "sampler.h"

namespace foton {

struct Window2 {
    float u0 = 0.f, v0 = 0.f, u1 = 1.f, v1 = 1.f;  // u0 <= u1, v0 <= v1, within [0, 1]
    bool contains(Point2 p) const { return p.x >= u0 && p.x <= u1 && p.y >= v0 && p.y <= v1; }
};

class WindowedDistribution {
  public:
    WindowedDistribution() = default;
    // weights[row * nu + column] (rows along v), non-negative and finite.
    WindowedDistribution(const std::vector<float>& weights, int nu, int nv);
    bool empty() const { return nu_ == 0; }

    // The integral of the piecewise-constant function over the window.
    double integral(const Window2& w) const;
    // A point of the window drawn in proportion to the function there, and its density
    // with respect to area (the function over the window's integral); false when the
    // function is zero over the window.
    bool sample(Point2 u, const Window2& w, Point2& p, float& pdf) const;
    float pdf(Point2 p, const Window2& w) const;

  private:
    // The function's integral over [0, x] x [0, y].
    double sat_at(double x, double y) const;
    float value(Point2 p) const;

    int nu_ = 0, nv_ = 0;
    std::vector<float> f_;            // per cell
    std::vector<double> sat_;         // (nu + 1) x (nv + 1) corner sums, cells of area 1 / (nu nv)
    std::vector<double> row_prefix_;  // per row, nu + 1 running sums of its cells' values
};

}  // namespace foton
