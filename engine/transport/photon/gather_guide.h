#pragma once
// Photon-map-guided importance sampling of final-gather directions (Jensen 1995,
// "Importance driven path tracing using the photon map"): the photons around a visible
// point tell from where light arrives, so a histogram of their power over the hemisphere
// is a density for the gather rays that follows the incident radiance.
//
// The hemisphere is parametrised by the cosine-weighted square (u1 = sin^2 theta,
// u2 = phi / 2 pi), cut into kRes x kRes cells of equal projected solid angle. A photon
// arriving per unit area from direction w has density proportional to L(w) cos(theta), so
// its luminance added to its cell makes the cell weights proportional to the integral of
// L cos over the cells: within a cell the direction is drawn with pdf proportional to cos,
// so for a Lambertian surface the estimator's weight f cos / pdf is constant where L is.
// Every cell also gets `floor` of the mean cell weight, so that no direction has zero
// density (light the photons missed is still found: the estimator stays unbiased).
#include <array>
#include <cstdint>

#include "engine/core/math.h"
#include "engine/core/sampler.h"

namespace foton {

class GatherGuide {
  public:
    static constexpr int kRes = 8;

    // Starts an empty histogram.
    void clear();
    // Adds a photon arriving from local direction `wi` (z up) with weight `w` (luminance of
    // its power); directions below the horizon are ignored.
    void add(const Vec3& wi, float w);
    // Turns the histogram into the sampling density; false when it holds no photon (the
    // caller should then sample the BSDF).
    bool finish(float floor = 0.1f);
    uint32_t photons() const { return photons_; }

    // A local direction for u in [0, 1)^2 (stratified u stay stratified: rows by u.x, the
    // cell in the row by u.y) and its solid-angle pdf.
    Vec3 sample(Point2 u, float& pdf) const;
    float pdf(const Vec3& wi) const;

  private:
    static int cell_of(const Vec3& wi, int& row, int& col);
    std::array<float, kRes * kRes> weight_{};  // histogram, then per-cell probabilities
    std::array<float, kRes + 1> row_cdf_{};
    std::array<float, kRes*(kRes + 1)> col_cdf_{};  // per row, conditional
    uint32_t photons_ = 0;
};

}  // namespace foton
