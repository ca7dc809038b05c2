#pragma once
// Visual importance for photon storage (the photon-mapping thesis' 6.7: importons, after
// Peter and Pietrek 1998 and Keller and Wald 2000). Before the photon pass, importons leave
// the camera through random pixels, pass mirrors and glass, and are counted where they meet a
// surface that takes photons (and, for final gathering, once more one diffuse bounce on, where
// the gather rays will look). A photon landing at x is then stored with probability
//
//     q(x) = clamp(I(x) / mean I, q_min, 1)
//
// and its power divided by q: the same expected map everywhere (no region gets q = 0, so the
// estimate stays unbiased), but of a given number of stored photons far more lie where the
// camera looks. In a scene whose lit geometry is mostly out of view, the photons the map holds
// (its memory, its kNN cost) then serve the image.
//
// I is a count per cell of a uniform grid over the scene's box, dilated to each cell's 3 x 3 x 3
// neighbourhood: a density estimate gathers photons from around a point, not only from its cell.
#include <cstdint>
#include <vector>

#include "engine/accel/intersector.h"
#include "engine/core/math.h"
#include "engine/scene/scene.h"

namespace foton {

struct ImportonSettings {
    uint64_t count = 0;            // importons traced (0: none, every photon stored)
    uint32_t diffuse_bounces = 0;  // 1 for final gathering: importance one bounce on too
    float min_probability = 0.05f;
    uint32_t max_specular = 8;  // delta bounces an importon may make
};

class ImportonMap {
  public:
    // Traces the importons (in parallel; the map does not depend on the thread count).
    void build(const Scene& scene, const Intersector& accel, const ImportonSettings& s,
               uint64_t seed);
    bool empty() const { return cells_.empty(); }
    // The probability q(x) of storing a photon that lands at p.
    float store_probability(const Vec3& p) const;
    // Importons that reached a surface (what the map counts).
    uint64_t recorded() const { return recorded_; }
    // The fraction of cells whose probability is 1 (the share of the scene kept whole).
    float full_fraction() const;

  private:
    std::size_t cell_of(const Vec3& p) const;

    Bounds3 bounds_;
    int res_[3] = {0, 0, 0};
    Vec3 inv_cell_;
    std::vector<float> cells_;  // q per cell
    float min_probability_ = 1.f;
    uint64_t recorded_ = 0;
};

}  // namespace foton
