#include "ao.h"

#include <any>
#include <cmath>

#include "engine/core/rng.h"
#include "engine/core/rng_streams.h"
#include "engine/core/warp.h"
#include "engine/transport/common/camera_integrator.h"
#include "engine/transport/common/surface.h"
#include "engine/transport/run/camera_driver.h"

namespace foton {

namespace {

// The row's parse leaves AoSettings in `own`; settings made by hand (tests) take the defaults.
AoSettings own_settings(const RenderSettings& settings) {
    const AoSettings* ao = std::any_cast<AoSettings>(&settings.own);
    return ao ? *ao : AoSettings{};
}

struct AoWorkspace : IntegratorWorkspace {
    RayBatch rays, probes;
    HitBatch hits;
    std::vector<uint8_t> occluded;
};

class AoIntegrator : public CameraIntegrator {
  public:
    AoIntegrator(const Scene& scene, const RenderSettings& settings, const Intersector& accel,
                 uint64_t seed)
        : scene_(scene),
          settings_(settings),
          ao_(own_settings(settings)),
          accel_(accel),
          seed_(seed) {}
    std::unique_ptr<IntegratorWorkspace> make_workspace() const override {
        return std::make_unique<AoWorkspace>();
    }
    void trace_phase(uint32_t /*phase*/, const std::vector<SampleJob>& jobs,
                     IntegratorWorkspace& base, std::vector<RGB>& radiance,
                     RenderStats& stats) const override {
        AoWorkspace& ws = static_cast<AoWorkspace&>(base);
        StageClock clock;
        ws.rays.clear();
        generate_camera_rays(scene_, settings_.sampler, jobs, seed_, ws.rays);
        radiance.assign(jobs.size(), RGB{0.f});
        stats.camera_rays += ws.rays.size();
        stats.add(Stage::Generate, ws.rays.size(), clock);
        accel_.intersect(ws.rays, ws.hits, stats.trace);
        stats.add(Stage::Intersect, ws.rays.size(), clock);
        // Probe rays over the cosine-weighted hemisphere of the shading normal; those below the
        // geometric surface count as closed.
        ws.probes.clear();
        const float tmax = ao_.distance > 0.f ? ao_.distance : kInfinity;
        for (std::size_t i = 0; i < ws.rays.size(); ++i) {
            if (ws.hits.geom[i] == kNoHit) continue;
            const SurfacePoint sp = surface_at(scene_, ws.rays, ws.hits, i);
            // Face the side the camera sees.
            const Vec3 toward = -ws.rays.direction(i);
            const Vec3 ng = dot(sp.ng, toward) < 0.f ? -sp.ng : sp.ng;
            const Vec3 ns = dot(sp.ns, ng) < 0.f ? -sp.ns : sp.ns;
            const warp::Frame frame(ns);
            const uint64_t id = jobs[ws.rays.id[i]].id;
            for (uint32_t k = 0; k < ao_.samples; ++k) {
                const Vec3 wi = frame.to_world(
                    warp::cosine_hemisphere({rng::uniform(seed_, kAoStream, id, 2 * k),
                                             rng::uniform(seed_, kAoStream, id, 2 * k + 1)}));
                if (dot(wi, ng) <= 0.f) continue;
                ws.probes.push(offset_origin(sp, wi), wi, 0.f, tmax, ws.rays.id[i]);
            }
        }
        stats.add(Stage::Shade, ws.rays.size(), clock);
        if (ws.probes.empty()) return;
        accel_.occluded(ws.probes, ws.occluded, stats.trace);
        stats.shadow_rays += ws.probes.size();
        const float w = 1.f / float(ao_.samples);
        for (std::size_t r = 0; r < ws.probes.size(); ++r)
            if (!ws.occluded[r]) radiance[ws.probes.id[r]] += RGB{w};
        stats.add(Stage::Occlusion, ws.probes.size(), clock);
    }

  private:
    const Scene& scene_;
    const RenderSettings& settings_;
    AoSettings ao_;
    const Intersector& accel_;
    uint64_t seed_;
};

}  // namespace

void parse_ao(const ParamSet& params, RenderSettings& settings) {
    AoSettings ao;
    ao.samples = uint32_t(params.integer("ao_samples", ao.samples, 1, 65536));
    ao.distance = params.real("ao_distance", ao.distance, 0.f);
    settings.own = ao;
}

RenderResult render_ao(const Scene& scene, const RenderSettings& settings, const Intersector& accel,
                       const RenderOptions& options) {
    const AoIntegrator integrator(scene, settings, accel, options.seed);
    return render_camera(scene, settings, integrator, options);
}

}  // namespace foton
