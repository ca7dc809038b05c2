#pragma once
// Photon-guided path tracing (after Jensen 1995, "Importance driven path tracing using the
// photon map"), kept unbiased by a one-sample mixture. A pre-pass traces photons; those that
// arrive at a diffuse surface straight off a mirror or through glass (the light next event
// estimation cannot sample, which BSDF sampling finds by chance: the fireflies) are binned by
// where they land (a voxel of the scene's grid and the axis their surface faces) into a
// histogram of their incident directions over the sphere. A path's diffuse vertex looks up
// its bin and draws its next direction from the histogram with probability `fraction`, else
// from the BSDF; the weight divides by the mixture's density, and MIS against next event
// estimation uses the same density, so every direction the BSDF can sample keeps its
// weight and the estimate stays unbiased. Smooth diffuse interreflection is left to the BSDF's
// cosine sampling, which suits it; without next event estimation the direct photons join in.
#include <cstdint>
#include <vector>

#include "engine/core/math.h"
#include "engine/core/sphere_histogram.h"
#include "engine/core/warp.h"
#include "engine/scene/bsdf.h"
#include "engine/transport/common/guide_mixture.h"
#include "engine/transport/path/path_guide_settings.h"
#include "engine/transport/photon/photon_map.h"

namespace foton {

class PathGuide {
  public:
    static constexpr uint32_t kMaxCells = kMaxGuideCells;

    // Bins `photons` with any of `flags` (the photon flags that guide) over a grid of
    // settings.cells (at most kMaxCells) voxels along the longest side of `bounds`; bins with
    // fewer than
    // settings.min_photons photons are left out (their vertices sample the BSDF).
    void build(const PhotonMap& photons, uint8_t flags, const Bounds3& bounds,
               const PathGuideSettings& settings);

    std::size_t size() const { return bins_.size(); }
    bool empty() const { return bins_.empty(); }
    std::size_t memory_bytes() const;
    // The bin of a vertex at p whose geometric normal (facing the arriving path) is ng; -1
    // when it has none.
    int find(const Vec3& p, const Vec3& ng) const;
    const SphereHistogram& histogram(int bin) const { return bins_[std::size_t(bin)]; }
    // The mixture a vertex samples with, bin b (>= 0) and guide fraction alpha.
    GuideMixture mixture(int bin, float alpha) const { return {&histogram(bin), alpha}; }

  private:
    // The bin slot of a point and its surface's normal: voxel, then the facing axis and sign.
    std::size_t slot(const Vec3& p, const Vec3& n) const;
    Vec3 origin_;
    float inv_cell_ = 0.f;
    int res_[3] = {0, 0, 0};
    std::vector<int32_t> index_;  // slot -> bins_ (-1: none); a dense grid, looked up per vertex
    std::vector<SphereHistogram> bins_;
};

// Whether a vertex with this BSDF is guided: diffuse lobes only (a guide that follows the
// incident light is a poor density for a glossy lobe, and delta lobes need none).
inline bool guidable(const Bsdf& bsdf) {
    return bsdf.has_non_delta() && (bsdf.flags() & (kGlossy | kSpecular)) == 0;
}

// Draws the next direction from the mixture: u_choice < alpha takes the guide, otherwise the
// BSDF (with u_choice stretched back to [0, 1) for its lobe choice). bs.pdf is the mixture's
// density and bs.f the BSDF's value, so f |cos| / pdf is the sample's weight; bsdf_pdf is the
// BSDF's own density of the direction. False when the direction carries nothing (a guided
// direction the BSDF does not scatter into).
bool sample_mixture(const Bsdf& bsdf, const Vec3& wo, const warp::Frame& frame,
                    const BsdfContext& ctx, const GuideMixture& mix, float u_choice, Point2 u,
                    BsdfSample& bs, float& bsdf_pdf);

}  // namespace foton
