#pragma once
// The beam radiance estimate (Jarosz, Zwicker and Jensen 2008): the radiance the volume
// photons scatter into a whole ray segment through a medium, gathered in one query instead of
// at one sampled point. With photon discs of radius r facing the ray (photon_discs.h),
//
//   L_in = sum over photons p within r of the segment of T(t_p) f_p(wo, wi_p) power_p / (pi r^2),
//
// t_p the point of the ray nearest the photon, T the transmittance from the ray's origin to it,
// f_p the Henyey-Greenstein phase function. (The disc kernel is the uniform ball kernel of the
// point estimate integrated along the ray and averaged over the disc: consistent as r -> 0.)
// T is exact in homogeneous media; in grid media one ratio-tracking walk along the segment
// gives it at every t at once (its running product up to t is an unbiased estimate of T(t)).
#include <algorithm>
#include <cstdint>
#include <vector>

#include "engine/scene/medium.h"
#include "engine/transport/common/medium_tracking.h"
#include "photon_discs.h"

namespace foton {

// What the beam estimate of one segment gives: the in-scattered radiance (before the path's
// throughput) and the segment's transmittance, which the path carries on with.
struct BeamEstimate {
    RGB in{0.f};
    RGB transmittance{1.f};
};

// The transmittance of medium m over [0, t) for every t: exact (homogeneous) or the running
// product of one ratio-tracking walk (grid media), recorded as (t_k, product after t_k).
class SegmentTransmittance {
  public:
    template <class Uniform>
    void walk(const Medium& m, const Vec3& o, const Vec3& d, float t_end, Uniform&& u) {
        m_ = &m;
        steps_.clear();
        if (m.homogeneous()) return;
        ratio_track_grid(m, o, d, t_end, u, [&](float t, const RGB& tr) {
            steps_.push_back({t, tr});
        });
    }
    RGB at(float t) const {
        if (m_->homogeneous()) return m_->transmittance(t);
        const auto it = std::upper_bound(steps_.begin(), steps_.end(), t,
                                         [](float v, const Step& s) { return v < s.t; });
        return it == steps_.begin() ? RGB{1.f} : std::prev(it)->tr;
    }

  private:
    struct Step {
        float t;
        RGB tr;
    };
    const Medium* m_ = nullptr;
    std::vector<Step> steps_;
};

// The beam estimate along o + t d, t in [0, t_end) (kInfinity: nothing ahead), in medium m,
// towards wo = -d; photons with any of `skip`'s flags are left out.
template <class Uniform>
BeamEstimate beam_estimate(const PhotonDiscs& discs, const PhotonMap& volume, const Medium& m,
                           const Vec3& o, const Vec3& d, float t_end, uint8_t skip,
                           SegmentTransmittance& tr, Uniform&& u) {
    BeamEstimate b;
    tr.walk(m, o, d, t_end, u);
    const float kernel = 1.f / (kPi * discs.radius() * discs.radius());
    discs.along(o, d, t_end, [&](uint32_t i, float t, float) {
        if (volume.flags(i) & skip) return;
        b.in += tr.at(t) * volume.power(i) * henyey_greenstein(dot(-d, volume.incident(i)), m.g);
    });
    b.in *= kernel;
    b.transmittance = tr.at(t_end);
    return b;
}

}  // namespace foton
