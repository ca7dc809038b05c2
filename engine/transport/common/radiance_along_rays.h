#pragma once
// The narrow interface through which the irradiance cache (secondary = path) asks for the
// radiance that rays leaving a scattering vertex bring back, without knowing who traces
// them: the path integrator implements it, the cache depends only on this header.
#include <cstdint>
#include <memory>
#include <vector>

#include "camera_integrator.h"
#include "engine/core/ray_batch.h"
#include "engine/core/rgb.h"
#include "engine/core/stats.h"

namespace foton {

class RadianceAlongRays {
  public:
    virtual ~RadianceAlongRays() = default;
    virtual std::unique_ptr<IntegratorWorkspace> make_workspace() const = 0;
    // Ray i adds what it brings back to radiance[rays.id[i]], its random numbers keyed by
    // keys[rays.id[i]]; the length of its first segment goes to first_dist[rays.id[i]]. The
    // vertex's own light sample stands for its direct light, so emission the first segment
    // finds is not counted.
    virtual void radiance_along(const RayBatch& rays, const std::vector<uint64_t>& keys,
                                IntegratorWorkspace& ws, std::vector<RGB>& radiance,
                                float* first_dist, RenderStats& stats) const = 0;
};

}  // namespace foton
