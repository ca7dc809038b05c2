#pragma once
// Path tracing and distributed ray tracing as one wavefront (the photon-mapping thesis,
// chapter 4; Cook et al. 1984). Per bounce the live paths of the batch are intersected, then
// shaded: emission found by the ray (MIS-weighted against light sampling), one next event
// estimation shadow ray, one BSDF-sampled continuation with Russian roulette; the shadow
// rays are tested in one batch and their contributions accumulated.
//
// `path`: BSDF importance sampling + next event estimation combined by the balance, power
// or maximum heuristic (or NEE alone, or BSDF sampling alone), Russian roulette from
// rr_depth scattering vertices, max_depth vertices at most (pbrt's convention: NEE at
// vertices 1..max_depth, emission found up to the segment after the last one).
//
// `distributed`: Cook's distributed ray tracer. Diffuse lobes take only direct light, from
// every light with light_samples shadow rays each (soft shadows); glossy and specular lobes
// are followed by sampling them (glossy reflection); a thin-lens camera gives depth of
// field. No diffuse interreflection: the ambient term stands in for it.
#include "camera_integrator.h"
#include "engine/accel/intersector.h"
#include "engine/core/ray_batch.h"
#include "engine/scene/light_set.h"

namespace foton {

struct PathWorkspace : IntegratorWorkspace {
    RayBatch rays, next, shadow;
    HitBatch hits;
    std::vector<uint8_t> occluded;
    std::vector<RGB> shadow_value;
    // Per-path state, indexed by the job slot.
    std::vector<RGB> beta;
    std::vector<float> pdf_prev;         // solid-angle pdf of the BSDF sample that made the ray
    std::vector<uint8_t> specular_prev;  // ... and whether it came from a delta lobe
    std::vector<Vec3> p_prev;            // where that ray started
};

class PathIntegrator : public CameraIntegrator {
  public:
    PathIntegrator(const Scene& scene, const Intersector& accel, const LightSet& lights,
                   uint64_t seed, bool distributed);
    std::unique_ptr<IntegratorWorkspace> make_workspace() const override {
        return std::make_unique<PathWorkspace>();
    }
    void trace(const std::vector<SampleJob>& jobs, IntegratorWorkspace& ws,
               std::vector<RGB>& radiance, RenderStats& stats) const override;

  private:
    void shade(uint32_t depth, const std::vector<SampleJob>& jobs, PathWorkspace& ws,
               std::vector<RGB>& radiance) const;
    float rand(const SampleJob& j, uint32_t depth, uint32_t k) const;

    const Scene& scene_;
    const Intersector& accel_;
    const LightSet& lights_;
    uint64_t seed_;
    bool distributed_;
};

}  // namespace foton
