#pragma once
// The second pass of photon mapping: camera rays are followed through specular chains to
// their first non-specular hit (the visible point), which is shaded by
//   final gather (default): direct light by next event estimation, caustics from the caustic
//     map, and indirect light by N final-gather rays (sampled from the BSDF's non-delta
//     lobes, stratified) whose hits are shaded by the global map's radiance estimate;
//   direct visualisation: the global map's radiance estimate alone (the thesis' fast,
//     biased mode: direct, indirect and caustics all from the photons).
// A material with both delta and non-delta lobes continues the chain or becomes the visible
// point with the probabilities of its lobe choice, each weighted by its inverse.
#include "engine/accel/intersector.h"
#include "engine/core/ray_batch.h"
#include "engine/core/warp.h"
#include "engine/scene/light_set.h"
#include "engine/transport/common/camera_integrator.h"
#include "engine/transport/common/shading_point.h"
#include "engine/transport/common/surface.h"
#include "engine/transport/irradiance_cache/cache_evaluator.h"
#include "engine/transport/photon/gather_guide.h"
#include "engine/transport/photon/photon_map.h"
#include "engine/transport/photon/reverse_photons.h"
#include "engine/transport/run/render_context.h"

namespace foton {

struct PhotonMaps {
    // `direct` is empty unless split_direct moved the first-hit photons out of `global`.
    PhotonMap global, caustic, shadow, direct;
    EstimateParams global_params, caustic_params;
};

// The final gather's hits, whose photon estimates are made together: every contribution is
// kept in the order the rays made it (a value, or a query answered by the batch), so the
// sums are the very same as adding them one by one.
struct FinalGatherBatch {
    struct Hit {
        SurfacePoint sp;
        const Material* m;
        Vec3 d;
        RGB w;
    };
    std::vector<Hit> hits;
    std::vector<RGB> L;                               // radiance of each hit from the photons
    std::vector<std::pair<uint32_t, int32_t>> order;  // slot, hit index (-1: values[i])
    std::vector<RGB> values;
    std::vector<uint32_t> lambert;  // hits read through the precomputed irradiance
    std::vector<RGB> rho, e;
    std::vector<uint8_t> found;
    PhotonMap::IrradianceQueries queries;
    std::vector<uint32_t> full;  // hits that take a full estimate
    std::vector<float> fx, fy, fz;
    kern::KnnBatchResult knn;
    ReversePhotons reverse;  // lookup="reverse"
};

struct PhotonCameraWorkspace : IntegratorWorkspace {
    RayBatch rays, next, shadow;
    HitBatch hits;
    GatherBuffers gather;
    std::vector<uint8_t> occluded;
    std::vector<RGB> beta, shadow_value;
    uint64_t saved = 0;  // shadow rays decided by shadow photons
    GatherGuide guide;
    FinalGatherBatch batch;
    // Irradiance cache: path length of each camera sample so far (for the pixel footprint).
    std::vector<float> path_length;
    CacheWorkspace cache;
    CacheWorkspace* cache_workspace() override { return &cache; }
};

class PhotonIntegrator : public CameraIntegrator {
  public:
    // With `cache`, indirect diffuse light comes from that irradiance cache instead of final
    // gathering at every point; visible points it cannot serve compute new records, which
    // the last trace() left in the workspace's cache part.
    PhotonIntegrator(const RenderContext& ctx, const PhotonMaps& maps,
                     const CacheEvaluator* cache = nullptr);
    std::unique_ptr<IntegratorWorkspace> make_workspace() const override {
        return std::make_unique<PhotonCameraWorkspace>();
    }
    // Camera gather: camera rays through specular chains to the visible points, their direct
    // light and caustics, and their final-gather rays queued; final gather: those rays traced
    // and shaded by the photon maps (or the irradiance cache's lookups resolved).
    uint32_t phases() const override { return 2; }
    // The components AOV: light seen directly or through specular chains (emitted), next
    // event estimation at the visible points (direct), the caustic map (caustic) and the
    // final gather or the cache (indirect); in direct visualisation the global map's estimate
    // (photon_map, the indirect light alone with split_direct).
    std::vector<std::string> components() const override;
    const char* phase_name(uint32_t p) const override {
        return p == 0 ? "camera-gather" : "final-gather";
    }
    void trace_phase(uint32_t phase, const std::vector<SampleJob>& jobs, IntegratorWorkspace& ws,
                     std::vector<RGB>& radiance, RenderStats& stats) const override;
    // Radiance leaving a final-gather hit towards -d, from the photons (global and, when
    // split, direct maps; precomputed irradiance on Lambertian surfaces).
    RGB photon_radiance(const struct SurfacePoint& sp, const Material& m, const Vec3& d) const;

  private:
    void shade_visible(const ShadingPoint& v, PhotonCameraWorkspace& ws,
                       std::vector<RGB>& radiance) const;
    void direct_light(const ShadingPoint& v, PhotonCameraWorkspace& ws,
                      std::vector<RGB>& radiance) const;
    void gather_rays(const ShadingPoint& v, PhotonCameraWorkspace& ws) const;
    // The photon estimates of every hit of the batch (photon_radiance for each, with the
    // precomputed-irradiance lookups made as one batched kNN per map).
    void photon_radiance_batch(FinalGatherBatch& b) const;
    // Traces ws.gather and adds what each ray brings back to radiance[ray id].
    void final_gather(PhotonCameraWorkspace& ws, std::vector<RGB>& radiance,
                      RenderStats& stats) const;
    float rand(uint64_t key, uint32_t depth, uint32_t k) const;

    const RenderContext ctx_;
    const PhotonMaps& maps_;
    const CacheEvaluator* const cache_;
};

}  // namespace foton
