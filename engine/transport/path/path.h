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
//
// With an irradiance cache (indirect="irradiance_cache"), `path` stops at the first diffuse
// vertex of each camera path (one reached through specular vertices only) whose non-delta
// lobes are Lambertian: its direct light from one light sample, its indirect light from the
// cache.
#include "engine/accel/intersector.h"
#include "engine/core/ray_batch.h"
#include "engine/scene/light_set.h"
#include "engine/transport/common/camera_integrator.h"
#include "engine/transport/common/kernel_materials.h"
#include "engine/transport/common/mis.h"
#include "engine/transport/common/path_sampler.h"
#include "engine/transport/common/radiance_along_rays.h"
#include "engine/transport/irradiance_cache/cache_evaluator.h"
#include "engine/transport/run/render_context.h"
#include "engine/transport/run/render_options.h"

namespace foton {

// What path tracing and Cook's distributed ray tracing do differently at a vertex, fixed when
// the integrator is made: one wavefront loop serves both.
struct VertexRules {
    bool nee = true;                  // a light sample at every non-delta vertex
    Mis mis;                          // how emission found by BSDF rays is weighed against it
    bool emission_whole = false;      // emission found by rays counts whole (no MIS)
    bool every_light = false;         // light_samples shadow rays to every light, not one chosen
    bool glossy_by_sampling = false;  // glossy lobes see area lights only by being sampled
    bool ambient = false;             // the thesis' ambient term stands in for interreflection
    bool guided = true;               // may follow a photon guide
    uint8_t continue_lobes = 0xff;    // the lobes a path continues through

    static VertexRules path(const RenderSettings& s) {
        VertexRules r;
        r.nee = s.nee;
        r.mis = Mis{s.mis, s.mis_beta};
        return r;
    }
    static VertexRules distributed() {
        VertexRules r;
        r.mis = Mis{MisHeuristic::None};
        r.emission_whole = true;
        r.every_light = true;
        r.glossy_by_sampling = true;
        r.ambient = true;
        r.guided = false;
        r.continue_lobes = uint8_t(kGlossy | kSpecular);
        return r;
    }
};

class PathGuide;

// What a path tracer may read besides the scene, fixed when it is made (path only, not
// distributed).
struct PathReaders {
    // Indirect light at the first diffuse vertex from this irradiance cache.
    const CacheEvaluator* cache = nullptr;
    // Diffuse vertices draw their next direction from this photon guide's mixture.
    const PathGuide* guide = nullptr;
};

struct PathWorkspace : IntegratorWorkspace {
    RayBatch rays, next, shadow;
    HitBatch hits;
    std::vector<uint8_t> occluded;
    std::vector<RGB> shadow_value;
    // Per-path state, indexed by the job slot.
    std::vector<RGB> beta;
    // The product of eta^2 over the refractions so far: beta times it is the path's
    // throughput without the radiance scaling of crossing into and out of dielectrics.
    std::vector<float> eta_scale;
    std::vector<float> pdf_prev;          // solid-angle pdf of the BSDF sample that made the ray
    std::vector<uint8_t> specular_prev;   // ... and whether it came from a delta lobe
    std::vector<Vec3> p_prev;             // where that ray started
    std::vector<Vec3> n_prev;             // ... and the geometric normal there
    std::vector<uint64_t> keys;           // what keys the path's random numbers
    std::vector<PathSampler> samplers;    // each path's random numbers (path_sampler.h)
    std::vector<uint8_t> chain_specular;  // only delta vertices so far (the cache's domain)
    // The path's class for lighting=direct|indirect: 0 before its first non-specular vertex,
    // 1 just after it, 2 once a second vertex (of any kind) follows it.
    std::vector<uint8_t> nondelta;
    std::vector<float> path_length;  // from the camera (the cache's pixel footprint)
    uint32_t first_depth = 0;        // > 0: paths started at a scattering vertex (radiance_along)
    CacheWorkspace cache;
    CacheWorkspace* cache_workspace() override { return &cache; }
    // The bounce's hits the SIMD kernels shade (batch entries), and their lanes.
    std::vector<uint32_t> diffuse_entries, specular_entries;
    // The diffuse kernel's hits by lobe group (plain diffuse, Phong, Beckmann, cos^e, GGX), joined
    // into diffuse_entries so that a register's lanes mostly run one glossy lobe's code.
    std::vector<uint32_t> diffuse_groups[kKernelGroups];
    KernelLanes lanes;
};

class PathIntegrator : public CameraIntegrator, public RadianceAlongRays {
  public:
    PathIntegrator(const RenderContext& ctx, const VertexRules& rules,
                   const PathReaders& readers = {});
    std::unique_ptr<IntegratorWorkspace> make_workspace() const override {
        return std::make_unique<PathWorkspace>();
    }
    void trace_phase(uint32_t phase, const std::vector<SampleJob>& jobs, IntegratorWorkspace& ws,
                     std::vector<RGB>& radiance, RenderStats& stats) const override;
    // Paths from camera rays made elsewhere (ids 0..n-1), with their samplers and keys: what
    // trace_phase does once it has made them (Metropolis light transport drives it with
    // primary-sample vectors, path_sampler.h). Takes the three by swapping them with the
    // workspace's (the caller gets buffers to refill, not copies).
    void trace_camera_paths(RayBatch& rays, std::vector<PathSampler>& samplers,
                            std::vector<uint64_t>& keys, IntegratorWorkspace& ws,
                            std::vector<RGB>& radiance, RenderStats& stats) const;
    // Path tracing onwards from rays leaving a scattering vertex (a cache record's hemisphere
    // rays); see RadianceAlongRays.
    void radiance_along(const RayBatch& rays, const std::vector<uint64_t>& keys,
                        IntegratorWorkspace& ws, std::vector<RGB>& radiance, float* first_dist,
                        RenderStats& stats) const override;

  private:
    // The camera paths of ws.rays (ids = slots), with ws.samplers and ws.keys set.
    void start_camera_paths(PathWorkspace& ws, std::vector<RGB>& radiance, RenderStats& stats,
                            StageClock& clock) const;
    // A bounce: the Lambertian hits through the SIMD kernel, the others one at a time.
    void shade(uint32_t depth, PathWorkspace& ws, std::vector<RGB>& radiance) const;
    void shade_vertex(uint32_t depth, std::size_t i, PathWorkspace& ws,
                      std::vector<RGB>& radiance) const;
    // The SIMD kernels' part (path_lanes.cpp, path_diffuse.cpp, path_specular.cpp).
    KernelMaterials kernel_materials() const;
    KernelKind kernel_of(const PathWorkspace& ws, std::size_t i) const;
    void pick_lane_lights(uint32_t depth, PathWorkspace& ws) const;
    static float kernel_light_kind(const Emitter& e);
    void put_kernel_light(uint32_t depth, std::size_t lane, const Emitter& e, const LightPick& pick,
                          LightSample& ls, PathWorkspace& ws) const;
    bool put_surface(std::size_t lane, std::size_t i, PathWorkspace& ws, bool need_point,
                     struct SurfacePoint& sp) const;
    void draw_lane_numbers(uint32_t depth, PathWorkspace& ws) const;
    // The path's part of a lane (throughput, eta^2 product, the ray's direction); its slot.
    uint32_t put_path(std::size_t lane, PathWorkspace& ws) const;
    // The sampler's number k of bounce `depth` for a lane: from the drawn table's row `row`
    // when the chunk has one (draw_lane_numbers), else drawn now.
    float lane_number(const PathWorkspace& ws, std::size_t lane, uint32_t row, uint32_t depth,
                      uint32_t k) const;
    Point2 lane_number2(const PathWorkspace& ws, std::size_t lane, uint32_t row, uint32_t depth,
                        uint32_t k) const;
    // A bounce's hits of one kernel, chunk by chunk: fill, kernel, read back.
    void shade_lanes(uint32_t depth, KernelKind kind, PathWorkspace& ws) const;
    void fill_diffuse_lane(uint32_t depth, std::size_t lane, PathWorkspace& ws) const;
    void fill_specular_lane(uint32_t depth, std::size_t lane, PathWorkspace& ws) const;
    // The chunk's shadow and continuation rays into the batches, the paths' state (delta:
    // the specular kernel's lanes).
    void read_lanes(PathWorkspace& ws, bool delta) const;
    // The cache's vertex: true when it took the path over.
    bool shade_cached(uint32_t depth, const struct SurfacePoint& sp, const Material& m,
                      const Vec3& d, uint32_t slot, PathWorkspace& ws) const;
    void run(PathWorkspace& ws, std::vector<RGB>& radiance, float* first_dist, RenderStats& stats,
             StageClock& clock) const;
    // The path's number k of bounce `depth` (see path.cpp's dimensions).
    float rand(const PathWorkspace& ws, uint32_t slot, uint32_t depth, uint32_t k) const;
    // Numbers k and k + 1 together (the light position, the BSDF direction): one Sobol' pair.
    Point2 rand2(const PathWorkspace& ws, uint32_t slot, uint32_t depth, uint32_t k) const;

    const RenderContext ctx_;
    const VertexRules rules_;
    const CacheEvaluator* const cache_;
    const PathGuide* const guide_;
    const KernelMaterials kernels_;
};

// The table entries (registry/integrators.h): the tile driver over path tracing (with the
// irradiance cache when the settings ask for it) or Cook's distributed ray tracing.
RenderResult render_path(const Scene& scene, const RenderSettings& settings,
                         const Intersector& accel, const RenderOptions& options);
// Path tracing guided by a photon pre-pass (path_guide.h): the guide's stages, then the
// camera pass as render_path's (guided_render.cpp).
RenderResult render_guided_path(const RenderContext& ctx, const RenderOptions& options);
// Path tracing onwards from rays leaving a scattering vertex, for the irradiance cache's
// secondary="path" in families that have no path tracer of their own (the registry hands it
// to them, so they need not include this family).
std::unique_ptr<RadianceAlongRays> make_path_onwards(const RenderContext& ctx);
RenderResult render_distributed(const Scene& scene, const RenderSettings& settings,
                                const Intersector& accel, const RenderOptions& options);

}  // namespace foton
