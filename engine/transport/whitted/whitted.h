#pragma once
// Whitted ray tracing (the first thesis) as a wavefront: per tile, camera rays are generated
// into a RayBatch, intersected, shaded into a batch of shadow rays (with the contribution
// each carries if unoccluded) and a batch of reflected/refracted rays (with their path
// weights), the shadow rays are tested, and the loop repeats on the secondary batch until
// it is empty, the depth limit is reached, or every weight falls below the cut-off.
#include "engine/accel/intersector.h"
#include "engine/core/aligned.h"
#include "engine/core/ray_batch.h"
#include "engine/core/rgb.h"
#include "engine/scene/light_set.h"
#include "engine/transport/common/camera_integrator.h"
#include "engine/transport/common/shading_point.h"
#include "engine/transport/common/surface.h"
#include "engine/transport/run/render_options.h"
#include "engine/transport/run/render_settings.h"

namespace foton {

// Per-thread scratch reused from tile to tile.
struct WhittedWorkspace : IntegratorWorkspace {
    RayBatch rays, next, shadow;
    HitBatch hits;
    std::vector<RGB> weight, next_weight, shadow_value;
    std::vector<uint8_t> occluded;
};

class WhittedIntegrator : public CameraIntegrator {
  public:
    WhittedIntegrator(const Scene& scene, const RenderSettings& settings, const Intersector& accel,
                      uint64_t seed);
    std::unique_ptr<IntegratorWorkspace> make_workspace() const override {
        return std::make_unique<WhittedWorkspace>();
    }
    void trace_phase(uint32_t phase, const std::vector<SampleJob>& jobs, IntegratorWorkspace& ws,
                     std::vector<RGB>& radiance, RenderStats& stats) const override;

  private:
    void generate(const std::vector<SampleJob>& jobs, WhittedWorkspace& ws) const;
    void shade(uint32_t depth, const std::vector<SampleJob>& jobs, WhittedWorkspace& ws,
               std::vector<RGB>& radiance) const;
    // Queues a shadow ray per light sample, carrying weight * brdf(wi) * incident * cos: the
    // thesis' point, directional, spot and area lights, emissive objects, the environment.
    // `behind`: lights behind the surface count too (a rough dielectric transmits them).
    template <class Brdf>
    void direct_light(const SurfacePoint& sp, const Brdf& brdf, const RGB& weight, uint32_t slot,
                      uint64_t sample_index, uint32_t depth, WhittedWorkspace& ws,
                      bool behind = false) const;
    // The physically based materials under the Whitted model: their BSDF lit by the point,
    // directional, spot and area lights, and their delta lobes followed recursively.
    // A generic (BSDF) material: ambient, direct light and the specular directions; v.key
    // keys the area lights' samples.
    void shade_generic(const ShadingPoint& v, WhittedWorkspace& ws,
                       std::vector<RGB>& radiance) const;

    const Scene& scene_;
    const RenderSettings& settings_;
    const Intersector& accel_;
    uint64_t seed_;
    // Emissive objects (spheres and meshes with <emission>) light surfaces as area lights
    // do: `light_samples` shadow rays each, drawn as next event estimation draws them.
    LightSet lights_;
    std::vector<uint32_t> emissive_;  // their indices in lights_
    bool sampled_lights_ = false;     // area lights, emissive objects or an environment
};

// The table entry (registry/integrators.h): the tile driver over this integrator.
RenderResult render_whitted(const Scene& scene, const RenderSettings& settings,
                            const Intersector& accel, const RenderOptions& options);

}  // namespace foton
