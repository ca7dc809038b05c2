#pragma once
// Projection maps for point and spot lights (the photon-mapping thesis, 5.3.2; Jensen's
// original form): the directions from the light binned as the cells of a cube map, and only
// the bins through which some geometry is seen (the scene's voxel outline, each voxel's
// corners projected onto each cube face it lies in front of; a voxel across a face's plane
// keeps that whole face) and, for a spot, that reach into its cone, emit. A direction is drawn
// by picking a kept bin by its solid angle and a point of its face cell uniformly: its density
// is (bin's solid angle / kept solid angle) / cell area x (1 + u^2 + v^2)^(3/2). Every
// direction in which geometry lies is in a kept bin, so the estimate stays unbiased.
#include <cstdint>
#include <vector>

#include "engine/core/math.h"
#include "engine/core/sampler.h"

namespace foton {

struct Scene;

class DirectionProjection {
  public:
    static constexpr int kFaceRes = 32;  // bins per cube face side
    static constexpr int kVoxels = 32;   // the outline's grid per scene axis

    // The map of the directions from p; cos_max > -1: only those within the cone of that
    // cosine around `axis` (a spot's outer cone).
    void build(const Scene& scene, const Vec3& p, const Vec3& axis, float cos_max);
    bool empty() const { return kept_.empty(); }
    // A direction from the kept bins and its solid-angle density.
    Vec3 sample(Point2 u, float& pdf) const;
    // The density sample() gives direction d (unit): 0 outside the kept bins.
    float pdf(const Vec3& d) const;
    // The kept solid angle over the whole sphere's 4 pi.
    float kept_fraction() const { return omega_ / (4.f * float(kPi)); }

  private:
    // The density of the direction at face coordinates (u, v) of kept bin k.
    float density(std::size_t k, float u, float v) const;

    std::vector<uint32_t> kept_;  // bin indices, ascending
    std::vector<float> cdf_;      // by solid angle, over kept_
    float omega_ = 0.f;           // the kept solid angle
};

}  // namespace foton
