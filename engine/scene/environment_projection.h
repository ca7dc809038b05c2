#pragma once
// Projection maps for environment light (the photon-mapping thesis, 5.3.2): an environment
// photon comes from a direction drawn from the sky and starts on a disc covering the scene's
// bounding sphere, across it; when the scene fills little of that disc most photons fly past.
// A directional light has one direction and one map (projection_map.h); the sky has all of
// them, so the directions are binned (the cells of a cube map, kFaceRes^2 per face) and each
// bin has a map in the plane across its central direction c. A ray along another direction d
// of the bin crosses that plane within R tan(angle(c, d)) of where the ray along c would (R
// the bounding radius), so each bin's map keeps the cells under the scene's occupied voxels'
// projections grown by R tan of the bin's widest angle: every line from the sky through
// geometry starts in a kept cell, and the estimate stays unbiased.
//
// A photon along d from the bin of c starts uniformly over the kept area A: its density in the
// plane across d is 1 / (A |c . d|).
#include <vector>

#include "engine/core/math.h"
#include "engine/core/sampler.h"
#include "projection_map.h"

namespace foton {

struct Scene;

class EnvironmentProjection {
  public:
    static constexpr int kFaceRes = 32;  // bins per cube face side: 6,144 bins
    static constexpr int kMapRes = 32;   // cells per map side
    static constexpr int kVoxels = 32;   // occupancy grid per scene axis

    // The maps of `scene` about its bounding sphere (center, radius).
    void build(const Scene& scene, const Vec3& center, float radius);
    bool empty() const { return bins_.empty(); }

    // The start of a ray from the sky direction wi (unit, towards the sky), travelling along
    // -wi: a point uniform over the kept cells of wi's bin, moved upstream out of the bounding
    // sphere; `pdf_pos` is its density across the ray (per unit area perpendicular to it).
    void sample(const Vec3& wi, Point2 u, Vec3& origin, float& pdf_pos) const;
    // The density sample() gives rays from wi (its kept cells: every ray through geometry).
    float pdf_pos(const Vec3& wi) const;
    // Whether the ray from the sky direction wi through the point p starts in a kept cell (it
    // must, for any p on geometry: the maps' promise, which the tests check).
    bool covers(const Vec3& wi, const Vec3& p) const;
    // The mean over bins of the kept area against the disc's pi R^2 (what is saved: the rest).
    float kept_fraction() const;

  private:
    struct Bin {
        Vec3 c, s, t;  // central direction and the map's plane
        ProjectionMap map;
    };
    std::size_t bin_of(const Vec3& wi) const;

    std::vector<Bin> bins_;
    Vec3 center_;
    float radius_ = 0.f;
};

}  // namespace foton
