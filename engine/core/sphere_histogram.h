#pragma once
// A piecewise-constant density over the sphere of directions, for guiding: the sphere is cut
// into kRows x kCols cells of equal solid angle (rows by z = cos theta, columns by phi), a
// histogram of weighted directions is made into cell probabilities, and directions are drawn
// uniformly within the chosen cell. Its pdf of a direction is p_cell / (4 pi / cells).
#include <array>
#include <cstdint>

#include "engine/core/math.h"
#include "engine/core/sampler.h"

namespace foton {

class SphereHistogram {
  public:
    static constexpr int kRows = 16, kCols = 16, kCells = kRows * kCols;

    void clear();
    // Adds weight w arriving along unit direction d (world space).
    void add(const Vec3& d, float w);
    uint32_t count() const { return count_; }
    // Makes the density: `floor` of the total is spread evenly over the cells so that no
    // direction has zero density. False when nothing (or no weight) was added.
    bool finish(float floor);

    // A direction for u in [0, 1)^2 and its solid-angle pdf.
    Vec3 sample(Point2 u, float& pdf) const;
    float pdf(const Vec3& d) const { return p_[std::size_t(cell_of(d))] * kDensity; }

  private:
    static constexpr float kDensity = float(kCells) / (4.f * kPi);  // 1 / cell solid angle
    static int cell_of(const Vec3& d);
    std::array<float, kCells> p_{};   // weights, then cell probabilities
    std::array<float, kRows> row_{};  // row probabilities
    uint32_t count_ = 0;
};

}  // namespace foton
