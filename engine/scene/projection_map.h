#pragma once
// A projection map for light arriving from one direction (the photon-mapping thesis, 5.3.2;
// Jensen 1996): photons of a directional light start on a square over the scene's bounding
// sphere, seen along the light, and most of that square lies over nothing when the scene is
// small in it. The square is cut into cells; the cells some object's projection touches are
// kept (conservatively: every triangle's and sphere's projected bounding box, slightly
// grown), and emission starts only there, uniformly over their area. Every surface point
// projects into a kept cell, so the density 1 / area() holds wherever light can arrive and
// the estimate stays unbiased; only the photons that would have missed are saved.
#include <cstdint>
#include <vector>

#include "engine/core/math.h"
#include "engine/core/sampler.h"

namespace foton {

struct Scene;

class ProjectionMap {
  public:
    // The map for light travelling along unit `dir` over the sphere (center, radius), in the
    // plane spanned by `s` and `t` (a frame around dir), res x res cells.
    void build(const Scene& scene, const Vec3& s, const Vec3& t, const Vec3& center, float radius,
               int res = 64);
    bool empty() const { return kept_.empty(); }
    // A point of the kept cells, uniform over their area, in the plane's (s, t) coordinates
    // about the centre.
    Point2 sample(Point2 u) const;
    float area() const { return float(kept_.size()) * cell_ * cell_; }
    // The kept fraction of the square (what the map saves: 1 - this of the photons).
    float coverage() const { return float(kept_.size()) / float(res_ * res_); }

  private:
    int res_ = 0;
    float radius_ = 0.f, cell_ = 0.f;
    std::vector<uint32_t> kept_;  // cell indices, row-major from (-radius, -radius)
};

}  // namespace foton
