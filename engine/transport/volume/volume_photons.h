#pragma once
// Photons through participating media (Jensen & Christensen 1998): emitted from the lights as
// photon mapping's are, their flights through a medium sampled as camera paths' are
// (transport/common/medium_tracking.h), stored where they scatter in a medium (the volume map)
// and where they meet a surface with a non-delta part (the surface map), continued by the
// phase function or the BSDF with Russian roulette on the flight's or the BSDF's weight.
// Interfaces are passed, changing medium. A photon starts in its light's medium (found once
// per light by common/medium_locate.h).
//
// Photons that scatter or land before any other bounce carry kPhotonDirect (the light's direct
// contribution there, which next event estimation can take instead).
//
// A volume photon's power is its flux times the flight's scattering weight T sigma_s / pdf:
// the stored photons' density per unit volume estimates sigma_s times the fluence, so
// sum p(wo, wi_p) power_p / (4/3 pi r^3) is the in-scattered radiance per unit length.
//
// Photon i of a pass is a pure function of (seed, pass, i); chunks of consecutive photons
// are traced as wavefronts and concatenated in order (the same maps for any thread count),
// and across MPI ranks each traces a contiguous share and every rank gets both maps whole.
#include <atomic>
#include <cstdint>
#include <vector>

#include "engine/accel/intersector.h"
#include "engine/core/cluster.h"
#include "engine/core/stats.h"
#include "engine/scene/light_set.h"
#include "engine/transport/photon/photon_map.h"

namespace foton {

struct VolumePhotonMaps {
    PhotonMap surface, volume;
};

class VolumePhotonTracer {
  public:
    VolumePhotonTracer(const Scene& scene, const Intersector& accel, const LightSet& lights,
                       uint64_t seed);
    // `emitted` photons of pass `pass`, bouncing at most max_depth times; stops between
    // chunks once `cancel` is set.
    VolumePhotonMaps run(uint64_t pass, uint64_t emitted, uint32_t max_depth, RenderStats& stats,
                         const Cluster* cluster, const std::atomic<bool>* cancel) const;

  private:
    struct Work;
    void trace(uint64_t pass, uint64_t emitted, uint64_t first, uint32_t count, uint32_t max_depth,
               Work& ws, VolumePhotonMaps& out, RenderStats& stats) const;

    const Scene& scene_;
    const Intersector& accel_;
    const LightSet& lights_;
    uint64_t seed_;
    std::vector<int32_t> light_medium_;  // each emitter's medium
};

}  // namespace foton
