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
#include "camera_integrator.h"
#include "engine/accel/intersector.h"
#include "engine/core/ray_batch.h"
#include "engine/core/warp.h"
#include "engine/scene/light_set.h"
#include "gather_guide.h"
#include "irradiance_cache.h"
#include "photon_map.h"

namespace foton {

struct PhotonMaps {
    // `direct` is empty unless split_direct moved the first-hit photons out of `global`.
    PhotonMap global, caustic, shadow, direct;
    EstimateParams global_params, caustic_params;
};

// A visible point that found no usable cache record: a new record is computed there.
struct CacheRequest {
    Vec3 p, s, t, n;
    float r_min = 0.f;
    uint32_t slot = 0;
    RGB weight;          // beta * rho / pi: radiance per unit of irradiance
    uint32_t first = 0;  // its strata in cache_L / cache_dist
    uint64_t key = 0;    // of its random numbers
};

struct PhotonCameraWorkspace : IntegratorWorkspace {
    RayBatch rays, next, shadow, gather, gather_next;
    HitBatch hits;
    std::vector<uint8_t> occluded;
    std::vector<RGB> beta, shadow_value, gather_weight, gather_weight_next;
    uint64_t saved = 0;  // shadow rays decided by shadow photons
    GatherGuide guide;
    // Irradiance cache: path length of each camera sample so far (for the pixel footprint),
    // this batch's new records and the rays computing them.
    std::vector<float> path_length;
    std::vector<CacheRequest> requests;
    RayBatch cache_rays;
    TraceCounters cache_trace;
    std::vector<RGB> cache_L;
    std::vector<float> cache_dist;
    std::vector<IrradianceRecord> new_records;
    CacheCounters lookup;
};

class PhotonIntegrator : public CameraIntegrator {
  public:
    PhotonIntegrator(const Scene& scene, const Intersector& accel, const LightSet& lights,
                     const PhotonMaps& maps, uint64_t seed);
    std::unique_ptr<IntegratorWorkspace> make_workspace() const override {
        return std::make_unique<PhotonCameraWorkspace>();
    }
    void trace(const std::vector<SampleJob>& jobs, IntegratorWorkspace& ws,
               std::vector<RGB>& radiance, RenderStats& stats) const override;
    // Indirect diffuse light from this cache (read-only while tracing) instead of final
    // gathering at every point; visible points it cannot serve compute new records, which
    // the last trace() left in the workspace's new_records.
    void set_cache(const IrradianceCache* cache) { cache_ = cache; }

  private:
    void shade_visible(const struct SurfacePoint& sp, const Material& m, const Vec3& d,
                       const RGB& weight, uint32_t slot, const SampleJob& job, uint32_t depth,
                       PhotonCameraWorkspace& ws, std::vector<RGB>& radiance) const;
    void direct_light(const struct SurfacePoint& sp, const Material& m, const Vec3& wo,
                      const warp::Frame& frame, const RGB& weight, uint32_t slot,
                      const SampleJob& job, uint32_t depth, PhotonCameraWorkspace& ws,
                      std::vector<RGB>& radiance) const;
    void gather_rays(const struct SurfacePoint& sp, const Material& m, const Vec3& wo,
                     const warp::Frame& frame, const RGB& weight, uint32_t slot,
                     const SampleJob& job, uint32_t depth, PhotonCameraWorkspace& ws) const;
    // Radiance leaving a final-gather hit towards -d, from the photons (global and, when
    // split, direct maps; precomputed irradiance on Lambertian surfaces).
    RGB photon_radiance(const struct SurfacePoint& sp, const Material& m, const Vec3& d) const;
    // Traces ws.gather (weights ws.gather_weight) and adds what each ray brings back to
    // out[ray id]; with `first_dist`, the first segment's length goes to first_dist[id].
    void final_gather(PhotonCameraWorkspace& ws, std::vector<RGB>& out, float* first_dist,
                      RenderStats& stats) const;
    // Interpolates the cache at a Lambertian visible point, or queues a new record.
    void cache_indirect(const struct SurfacePoint& sp, const warp::Frame& frame, const RGB& weight,
                        uint32_t slot, const SampleJob& job, uint32_t depth,
                        PhotonCameraWorkspace& ws, std::vector<RGB>& radiance) const;
    // Computes the queued records and adds their irradiance to their samples.
    void compute_records(PhotonCameraWorkspace& ws, std::vector<RGB>& radiance,
                         RenderStats& stats) const;
    float rand(const SampleJob& j, uint32_t depth, uint32_t k) const;

    const Scene& scene_;
    const Intersector& accel_;
    const LightSet& lights_;
    const PhotonMaps& maps_;
    uint64_t seed_;
    const IrradianceCache* cache_ = nullptr;
    HemisphereStrata strata_;
};

}  // namespace foton
