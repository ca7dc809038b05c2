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

// The convex hull of 2D points, counter-clockwise (Andrew's monotone chain).
std::vector<Point2> convex_hull(std::vector<Point2> points);
// Marks the cells of `mark` (res x res, of side `cell` from (-half, -half)) that the convex
// polygon `hull` (counter-clockwise; with fewer than 3 points, its box) overlaps, each cell grown
// by `grow` on every side.
void mark_convex(const std::vector<Point2>& hull, float grow, int res, float half, float cell,
                 std::vector<uint8_t>& mark);

class ProjectionMap {
  public:
    // The map for light travelling along unit `dir` over the sphere (center, radius), in the
    // plane spanned by `s` and `t` (a frame around dir), res x res cells.
    void build(const Scene& scene, const Vec3& s, const Vec3& t, const Vec3& center, float radius,
               int res = 64);
    bool empty() const { return kept_.empty(); }
    // The map of the square of half-size `half` about `center` in the plane (s, t) for light
    // along directions near the plane's normal: the cells the projected boxes touch, each box's
    // projection grown by `grow` (how far another direction of the bundle can shift it).
    void build(const std::vector<Bounds3>& boxes, const Vec3& s, const Vec3& t, const Vec3& center,
               float half, float grow, int res);
    // A point of the kept cells, uniform over their area, in the plane's (s, t) coordinates
    // about the centre.
    Point2 sample(Point2 u) const;
    float area() const { return float(kept_.size()) * cell_ * cell_; }
    // Whether the point q of the plane ((s, t) coordinates about the centre) is in a kept cell.
    bool kept(Point2 q) const;
    // The kept fraction of the square (what the map saves: 1 - this of the photons).
    float coverage() const { return float(kept_.size()) / float(res_ * res_); }

  private:
    int res_ = 0;
    float radius_ = 0.f, cell_ = 0.f;
    // Cell indices, row-major from (-radius, -radius); 16 bits (res <= 256): an environment
    // has thousands of maps.
    std::vector<uint16_t> kept_;
};

}  // namespace foton
