#pragma once
// The volume photons as discs of one radius r that face every ray (Jarosz, Zwicker and Jensen
// 2008, "The beam radiance estimate for volumetric photon mapping"): a photon counts for a ray
// where the ray passes within r of it, at the point of the ray nearest to it. Kept in a binary
// BVH over the photons' spheres (kernels/bvh_build.h, binned SAH), walked once per ray
// segment: the beam estimate gathers a whole segment's photons in one query, where the point
// estimate gathers a ball's at one sampled point.
#include <cstdint>

#include "engine/core/math.h"
#include "engine/transport/photon/photon_map.h"
#include "kernels/bvh_build.h"

namespace foton {

class PhotonDiscs {
  public:
    // Over `photons` (kept by reference: it must outlive this), radius r.
    void build(const PhotonMap& photons, float r,
               const kern::BvhBuildParams::ParallelInvoke& parallel);
    float radius() const { return r_; }
    // Every photon within r of the segment o + t d, t in [0, t_end) (d unit), its nearest point
    // t_p on the ray within the segment: visit(photon index, t_p, squared distance).
    template <class Visit>
    void along(const Vec3& o, const Vec3& d, float t_end, Visit&& visit) const {
        if (!photons_) return;
        const kern::Ray1 ray{o.x, o.y, o.z, d.x, d.y, d.z, 0.f, t_end};
        const float r2 = r_ * r_;
        kern::walk_binary_bvh(
            bvh_, ray, [&] { return t_end; },
            [&](uint32_t i) {
                const Vec3 v = photons_->position(i) - o;
                const float t = dot(v, d);
                if (!(t >= 0.f && t < t_end)) return false;
                const float dist2 = length_squared(v - d * t);
                if (dist2 < r2) visit(i, t, dist2);
                return false;
            });
    }

  private:
    const PhotonMap* photons_ = nullptr;
    float r_ = 0.f;
    kern::BinaryBvh bvh_;
};

}  // namespace foton
