#pragma once
// Shadow rays through participating media: a light sample's value reaches its slot times the
// transmittance of every medium on the way, and the ray passes the surfaces that only bound
// media (interface materials), changing medium there. Any other surface blocks it. Traced as
// whole batches: each round finds every live ray's closest hit, and the rays that crossed an
// interface go on in the next round.
#include <cstdint>
#include <vector>

#include "engine/accel/intersector.h"
#include "engine/core/ray_batch.h"
#include "engine/core/rgb.h"
#include "engine/core/stats.h"
#include "engine/scene/scene.h"
#include "engine/scene/spectral_medium.h"
#include "medium_tracking.h"
#include "surface.h"

namespace foton {

// Which side of a hit surface a direction leaves to: the side its object's own normal points
// to (outside) or not.
inline bool leaves_outward(const SurfacePoint& sp, const Vec3& w) {
    return (dot(w, sp.ng) > 0.f) == sp.front_face;
}

// The medium a ray is in after leaving the surface of object `geom` along w, having been in
// `current` (scene/medium.h's rule: only boundaries change it).
inline int32_t medium_after(const Scene& scene, uint32_t geom, const SurfacePoint& sp,
                            const Vec3& w, int32_t current) {
    return scene.objects[geom].media.after(leaves_outward(sp, w), current);
}

// More interface crossings than this end a path (light paths, photons).
inline constexpr uint32_t kMaxPathCrossings = 256;

// A path that met an interface at sp (object geom) along d goes on through it in the medium
// beyond: its next ray into `next`, unless it has crossed too many.
inline void cross_interface(const Scene& scene, uint32_t geom, const SurfacePoint& sp,
                            const Vec3& d, uint32_t slot, int32_t& medium, uint32_t& crossings,
                            RayBatch& next) {
    if (++crossings > kMaxPathCrossings) return;
    medium = medium_after(scene, geom, sp, d, medium);
    next.push(offset_origin(sp, d), d, 0.f, kInfinity, slot);
}

// More interface crossings than this on one shadow ray block it (only a degenerate scene,
// such as many coincident boundaries, gets there).
inline constexpr uint32_t kMaxShadowCrossings = 64;

class MediumShadowRays {
  public:
    void clear();
    bool empty() const { return rays_.empty(); }
    std::size_t size() const { return rays_.size(); }
    // A shadow ray in `medium` that adds `value` times the transmittance to radiance[slot]
    // when it reaches tmax; `key` keys ratio tracking's random numbers.
    void push(const Vec3& origin, const Vec3& dir, float tmax, int32_t medium, uint32_t slot,
              const RGB& value, uint64_t key);
    // Traces every ray to its end (rounds of closest hits), adding what arrives. With
    // `wavelengths` (by slot: spectral paths, core/spectrum.h) the media are read at each
    // ray's path's wavelengths.
    void resolve(const Scene& scene, const Intersector& accel, TransmittanceEstimator estimator,
                 uint64_t seed, std::vector<RGB>& radiance, RenderStats& stats, StageClock& clock,
                 const std::vector<Wavelengths>* wavelengths = nullptr);

  private:
    struct State {
        uint32_t slot;
        int32_t medium;
        uint32_t crossings;
        uint32_t draws;
        uint64_t key;
        RGB value;
        Vec3 end;
    };
    RayBatch rays_, next_;
    HitBatch hits_;
    std::vector<State> state_, next_state_;
};

}  // namespace foton
