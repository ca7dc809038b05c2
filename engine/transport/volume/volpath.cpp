#include "volpath.h"

#include <any>
#include <cmath>

#include "engine/core/error.h"
#include "engine/core/rng.h"
#include "engine/core/rng_streams.h"
#include "engine/core/spectrum.h"
#include "engine/scene/light_set.h"
#include "engine/scene/spectral_medium.h"
#include "engine/transport/common/camera_integrator.h"
#include "engine/transport/common/medium_shadow.h"
#include "engine/transport/common/mis.h"
#include "engine/transport/common/next_event.h"
#include "engine/transport/common/path_sampler.h"
#include "engine/transport/common/spectral_paths.h"
#include "engine/transport/common/surface.h"
#include "engine/transport/common/wavefront.h"
#include "engine/transport/run/camera_driver.h"
#include "engine/transport/run/render_context.h"
#include "grid_flights.h"
#include "subsurface_exit.h"
#include "volpath_workspace.h"

namespace foton {

namespace {

// The path tracer's dimensions per vertex (common/path_sampler.h); a medium vertex takes the
// light's and the direction's the same way (the phase function has one lobe).
constexpr uint32_t kDimLightSelect = kPathDimLightSelect, kDimLight = kPathDimLight,
                   kDimBsdf = kPathDimBsdf, kDimRoulette = kPathDimRoulette;
// More interface crossings than this end a path: only a ray caught between coincident
// boundaries gets there.
constexpr uint32_t kMaxCrossings = 256;

class VolPathIntegrator : public CameraIntegrator {
  public:
    VolPathIntegrator(const RenderContext& ctx, const VolPathSettings& own)
        : ctx_(ctx),
          own_(own),
          mis_{ctx.settings.mis, ctx.settings.mis_beta},
          flight_prefix_(rng::stream_prefix(ctx.seed, kMediumStream)),
          wavelength_prefix_(rng::stream_prefix(ctx.seed, kWavelengthStream)),
          subsurface_prefix_(rng::stream_prefix(ctx.seed, kSubsurfaceStream)) {
        // Each subsurface medium's exit BSDF (the BSSRDF's directional part).
        for (const Subsurface& sub : ctx.scene.subsurfaces) {
            Material exit;
            exit.type = MaterialType::Generic;
            exit.bsdf.add(Lobe::subsurface_exit(sub.eta));
            exits_.push_back(exit);
        }
    }

    std::unique_ptr<IntegratorWorkspace> make_workspace() const override {
        return std::make_unique<VolPathWorkspace>();
    }

    void trace_phase(uint32_t, const std::vector<SampleJob>& jobs, IntegratorWorkspace& base,
                     std::vector<RGB>& radiance, RenderStats& stats) const override {
        VolPathWorkspace& ws = static_cast<VolPathWorkspace&>(base);
        StageClock clock;
        const std::size_t n = jobs.size();
        radiance.assign(n, RGB{0.f});
        ws.beta.assign(n, RGB{1.f});
        ws.eta_scale.assign(n, 1.f);
        ws.pdf_prev.assign(n, 0.f);
        ws.specular_prev.assign(n, 1);
        ws.p_prev.assign(n, Vec3{});
        ws.n_prev.assign(n, Vec3{});
        ws.medium.assign(n, ctx_.scene.camera_medium);
        ws.vertices.assign(n, 0);
        ws.rough.assign(n, 0);
        ws.crossings.assign(n, 0);
        ws.draws.assign(n, 0);
        ws.keys.resize(n);
        ws.samplers.resize(n);
        for (std::size_t i = 0; i < n; ++i) {
            ws.keys[i] = jobs[i].id;
            ws.samplers[i] =
                PathSampler::for_job(ctx_.settings.sampler, ctx_.scene, jobs[i], ctx_.seed);
        }
        if (own_.spectral) {
            ws.wavelengths.resize(n);
            for (std::size_t i = 0; i < n; ++i)
                ws.wavelengths[i] =
                    Wavelengths::sample(wavelength_number(wavelength_prefix_, ctx_.scene, jobs[i]));
        }
        ws.rays.clear();
        generate_camera_rays(ctx_.scene, ctx_.settings.sampler, jobs, ctx_.seed, ws.rays);
        stats.camera_rays += n;
        stats.add(Stage::Generate, n, clock);
        run_wavefront(
            ctx_.accel, ws.rays, ws.next, ws.hits, 0, std::numeric_limits<uint32_t>::max(), stats,
            clock,
            [&](uint32_t) {
                ws.shadow.clear();
                track_grid_flights(ws);
                for (std::size_t i = 0; i < ws.rays.size(); ++i) shade_ray(i, ws, radiance);
                stats.trace.merge(ws.probes);
                ws.probes = TraceCounters{};
            },
            [&](uint32_t) {
                ws.shadow.resolve(ctx_.scene, ctx_.accel, own_.transmittance, ctx_.seed, radiance,
                                  stats, clock, own_.spectral ? &ws.wavelengths : nullptr);
            });
        // A spectral path's values at its wavelengths become the sample's colour.
        if (own_.spectral)
            for (std::size_t i = 0; i < n; ++i) radiance[i] = ws.wavelengths[i].to_rgb(radiance[i]);
    }

  private:
    float flight_number(VolPathWorkspace& ws, uint32_t slot) const {
        return rng::uniform_from(flight_prefix_, ws.keys[slot], ws.draws[slot]++);
    }

    // The bounce's flights through grid media, all at once (grid_flights.h). Spectral paths
    // fly one at a time: each reads the media at its own wavelengths, so no two share the
    // majorant grid's scale the batch kernel takes.
    void track_grid_flights(VolPathWorkspace& ws) const {
        if (own_.spectral) {
            ws.flight_of.assign(ws.rays.size(), -1);
            return;
        }
        ws.flights.track_batch(ctx_.scene, ws.rays, ws.hits, ws.medium, ws.beta,
                               own_.flight_kernel == FlightKernel::Simd, ws.flight_of,
                               [&](uint32_t slot) { return flight_number(ws, slot); });
    }

    float rand(const VolPathWorkspace& ws, uint32_t slot, uint32_t k) const {
        return ws.samplers[slot].get1(ctx_.seed, ws.vertices[slot], k);
    }
    Point2 rand2(const VolPathWorkspace& ws, uint32_t slot, uint32_t k) const {
        return ws.samplers[slot].get2(ctx_.seed, ws.vertices[slot], k);
    }

    // Emitted radiance given in RGB as the path carries it: itself, or a spectral path's
    // values of its illuminant spectrum.
    RGB emitted(const VolPathWorkspace& ws, uint32_t slot, const RGB& le) const {
        return own_.spectral ? ws.wavelengths[slot].illuminant(le) : le;
    }

    // A flight through medium med, at the path's wavelengths when it is spectral.
    template <class Uniform>
    FreeFlight fly(const Medium& med, const VolPathWorkspace& ws, uint32_t slot, const Vec3& o,
                   const Vec3& d, float t_end, Uniform&& u) const {
        if (own_.spectral)
            return free_flight(SpectralMedium(med, ws.wavelengths[slot]), o, d, t_end,
                               ws.beta[slot], own_.free_flight, u);
        return free_flight(med, o, d, t_end, ws.beta[slot], own_.free_flight, u);
    }

    // Emission found by a sampled ray, weighed against next event estimation's density of
    // the same light point (`light_pdf`, evaluated only when needed).
    template <class LightPdf>
    float emission_weight(const VolPathWorkspace& ws, uint32_t slot, LightPdf&& light_pdf) const {
        if (ws.vertices[slot] == 0 || ws.specular_prev[slot] || !ctx_.settings.nee) return 1.f;
        if (mis_.heuristic == MisHeuristic::None) return 0.f;
        return mis_weight_bsdf(mis_, ws.pdf_prev[slot], light_pdf());
    }

    void shade_ray(std::size_t i, VolPathWorkspace& ws, std::vector<RGB>& radiance) const {
        const uint32_t slot = ws.rays.id[i];
        const uint32_t geom = ws.hits.geom[i];
        const Vec3 d = ws.rays.direction(i);
        RGB& beta = ws.beta[slot];
        if (const int32_t mi = ws.medium[slot]; mi != kNoMedium) {
            const Medium& med = ctx_.scene.media[std::size_t(mi)];
            const float t_end = geom == kNoHit ? kInfinity : ws.hits.t[i];
            auto u = [&] { return flight_number(ws, slot); };
            const FreeFlight f = ws.flight_of[i] >= 0
                                     ? ws.flights.result(std::size_t(ws.flight_of[i]))
                                     : fly(med, ws, slot, ws.rays.origin(i), d, t_end, u);
            // The medium's own light along the flight: no light sample finds it, full weight.
            if (!f.emitted.is_black()) radiance[slot] += beta * f.emitted;
            if (f.event == FreeFlight::Event::Absorb) return;
            beta *= f.weight;
            if (beta.is_black()) return;
            if (f.event == FreeFlight::Event::Scatter) {
                medium_vertex(slot, ws.rays.origin(i) + d * f.t, d, med, ws);
                return;
            }
        }
        if (geom == kNoHit) {
            if (!ctx_.scene.environment)
                radiance[slot] += beta * emitted(ws, slot, ctx_.scene.background);
            else
                radiance[slot] +=
                    beta * emitted(ws, slot, ctx_.scene.environment->Le(ws.rays.origin(i), d)) *
                    emission_weight(ws, slot, [&] {
                        return ctx_.lights.nee_environment_pdf(ws.rays.origin(i), d);
                    });
            return;
        }
        surface_vertex(i, ws, radiance);
    }

    // A scattering event inside medium `med` at p, the ray having come along d.
    void medium_vertex(uint32_t slot, const Vec3& p, const Vec3& d, const Medium& med,
                       VolPathWorkspace& ws) const {
        if (ws.vertices[slot] >= ctx_.settings.max_depth) return;
        const Vec3 wo = -d;
        const RGB& beta = ws.beta[slot];
        if (ctx_.settings.nee && !ctx_.lights.empty()) {
            LightPick pick;
            LightSample ls;
            if (ctx_.lights.pick(rand(ws, slot, kDimLightSelect), p, Vec3{}, pick) &&
                ctx_.lights.sample_li(pick.light, p, rand2(ws, slot, kDimLight),
                                      rand(ws, slot, kDimLight + 2), ls, pick.tri)) {
                const float phase = henyey_greenstein(dot(wo, ls.wi), med.g);
                const float pl = pick.pmf * ls.pdf;
                const bool full = mis_.heuristic == MisHeuristic::None ||
                                  ctx_.lights.emitter(pick.light).is_delta();
                const float w = full ? 1.f : mis_weight(mis_, pl, phase);
                const RGB value = beta * emitted(ws, slot, ls.Li) * (phase * w / pl);
                if (!value.is_black()) {
                    // A point in a medium has no surface to be pushed off.
                    SurfacePoint sp{};
                    sp.p = p;
                    const ShadowRay r = shadow_ray_to(sp, ls);
                    ws.shadow.push(r.origin, r.dir, r.tmax, ws.medium[slot], slot, value,
                                   rng::hash(ws.keys[slot], ws.vertices[slot], 0, 0));
                }
            }
        }
        // The phase function is sampled exactly: f / pdf = 1.
        Vec3 wi;
        const float pdf = sample_henyey_greenstein(wo, med.g, rand2(ws, slot, kDimBsdf + 1), wi);
        go_on(slot, p, Vec3{}, p, wi, pdf, false, ws);
    }

    void surface_vertex(std::size_t i, VolPathWorkspace& ws, std::vector<RGB>& radiance) const {
        const RenderSettings& rs = ctx_.settings;
        const uint32_t slot = ws.rays.id[i];
        const uint32_t geom = ws.hits.geom[i];
        const Vec3 d = ws.rays.direction(i);
        RGB& beta = ws.beta[slot];
        const SurfacePoint sp = surface_at(ctx_.scene, ws.rays, ws.hits, i);
        std::optional<Material> scratch;
        const Material& textured = ctx_.scene.material_at(geom, sp.tex(), scratch);
        const Material& seen =
            rs.regularize && ws.rough[slot] ? regularized_material(textured, scratch) : textured;
        const Material& m =
            own_.spectral ? material_at_wavelengths(seen, ws.wavelengths[slot], scratch) : seen;
        if (m.is_interface) {
            // No vertex: on into the medium beyond, with everything else as it was.
            if (++ws.crossings[slot] > kMaxCrossings) return;
            ws.medium[slot] = medium_after(ctx_.scene, geom, sp, d, ws.medium[slot]);
            ws.next.push(offset_origin(sp, d), d, 0.f, kInfinity, slot);
            return;
        }
        if (m.emits_towards(sp.front_face)) {
            const float w = emission_weight(ws, slot, [&] {
                const int li = ctx_.lights.emitter_of(geom);
                return li < 0 ? 0.f
                              : ctx_.lights.nee_pdf(uint32_t(li), ws.hits.prim[i], ws.p_prev[slot],
                                                    ws.n_prev[slot], sp.p, sp.ng);
            });
            radiance[slot] += beta * emitted(ws, slot, m.emission) * w;
        }
        if (ws.vertices[slot] >= rs.max_depth || m.bsdf.empty()) return;
        // A dispersive glass refracts each wavelength its own way: the hero goes on alone.
        if (own_.spectral && m.bsdf.disperses()) ws.wavelengths[slot].terminate_secondary(beta);
        ShadingPoint v(sp, m, d, beta, slot, ws.vertices[slot], ws.keys[slot]);
        if (own_.spectral) v.wavelengths = &ws.wavelengths[slot];
        if (rs.nee && m.bsdf.has_non_delta())
            direct_light(v, geom, rand(ws, slot, kDimLightSelect), rand2(ws, slot, kDimLight),
                         rand(ws, slot, kDimLight + 2), 0, ws);
        BsdfSample bs;
        const BsdfContext bctx{sp.front_face, Transport::Radiance};
        if (!m.bsdf.sample(v.wo, rand(ws, slot, kDimBsdf), rand2(ws, slot, kDimBsdf + 1), bctx, bs))
            return;
        const Vec3 wi = v.frame.to_world(bs.wi);
        // A direction on the wrong side of the true surface would leak light through it.
        const float side = dot(wi, sp.ng);
        if ((bs.flags & kTransmission) ? side >= 0.f : side <= 0.f) return;
        beta *= bs.f * (std::fabs(bs.wi.z) / bs.pdf);
        if (beta.is_black()) return;
        if (m.subsurface >= 0 && (bs.flags & kTransmission)) {
            subsurface_vertex(slot, geom, m, sp, ws);
            return;
        }
        ws.eta_scale[slot] *= bs.eta * bs.eta;
        ws.medium[slot] = medium_after(ctx_.scene, geom, sp, wi, ws.medium[slot]);
        go_on(slot, sp.p, sp.ng, offset_origin(sp, wi), wi, bs.pdf, bs.is_delta(), ws);
    }

    // Next event estimation at surface point v of object geom: a light sample's shadow ray,
    // through the medium on the side it leaves to; `which` tells a vertex's samples apart in
    // the shadow ray's numbers.
    void direct_light(const ShadingPoint& v, uint32_t geom, float u_pick, Point2 u_light,
                      float u_tri, uint64_t which, VolPathWorkspace& ws) const {
        LightPick pick;
        DirectSample ds;
        const uint32_t slot = v.slot;
        if (ctx_.lights.empty() || !ctx_.lights.pick(u_pick, v.sp.p, v.sp.ng, pick) ||
            !sample_light(ctx_.lights, {pick.light, pick.pmf, u_light, u_tri, pick.tri}, v,
                          kDiffuse | kGlossy, mis_, 1.f, ds))
            return;
        ws.shadow.push(ds.origin, ds.dir, ds.tmax,
                       medium_after(ctx_.scene, geom, v.sp, ds.dir, ws.medium[slot]), slot,
                       ds.value, rng::hash(ws.keys[slot], ws.vertices[slot], which, 0));
    }

    // Light the path sent into a subsurface material at `entry` comes out at a probe's exit
    // point (subsurface_exit.h), where the BSSRDF's directional part takes a light sample and
    // scatters the path on, as at a diffuse surface. Like pbrt-v4's volpath, the hop is no
    // vertex of its own: its numbers come from kSubsurfaceStream, not the path's sampler.
    void subsurface_vertex(uint32_t slot, uint32_t geom, const Material& m,
                           const SurfacePoint& entry, VolPathWorkspace& ws) const {
        float u[11];
        for (uint32_t k = 0; k < 11; ++k)
            u[k] = rng::uniform_from(subsurface_prefix_, ws.keys[slot],
                                     uint64_t(ws.vertices[slot]) * 16 + k);
        SubsurfaceExitPoint ex;
        if (!find_subsurface_exit(ctx_.scene, ctx_.accel, geom, m, entry, u, ws.probes, ex)) return;
        RGB& beta = ws.beta[slot];
        beta *= ex.weight;
        if (beta.is_black()) return;
        const Material& exit = exits_[std::size_t(m.subsurface)];
        // Seen from outside along the normal: the exit BSDF's frame is the outward normal's.
        const ShadingPoint v(ex.sp, exit, -ex.sp.ns, beta, slot, ws.vertices[slot], ws.keys[slot]);
        if (ctx_.settings.nee) direct_light(v, ex.geom, u[4], {u[5], u[6]}, u[7], 1, ws);
        BsdfSample bs;
        if (!exit.bsdf.sample(v.wo, u[8], {u[9], u[10]}, BsdfContext{true, Transport::Radiance},
                              bs))
            return;
        const Vec3 wi = v.frame.to_world(bs.wi);
        if (dot(wi, ex.sp.ng) <= 0.f) return;
        beta *= bs.f * (std::fabs(bs.wi.z) / bs.pdf);
        go_on(slot, ex.sp.p, ex.sp.ng, offset_origin(ex.sp, wi), wi, bs.pdf, false, ws);
    }

    // The path leaves vertex p (normal n, zero in a medium) from `origin` along wi, sampled
    // with density pdf: roulette, then the next bounce's ray.
    void go_on(uint32_t slot, const Vec3& p, const Vec3& n, const Vec3& origin, const Vec3& wi,
               float pdf, bool delta, VolPathWorkspace& ws) const {
        // Inside glass beta is 1/eta^2 of the carried throughput (see path.cpp).
        if (ws.vertices[slot] + 1 >= ctx_.settings.rr_depth) {
            const float q = std::min(1.f, ws.beta[slot].max_component() * ws.eta_scale[slot]);
            if (rand(ws, slot, kDimRoulette) >= q) return;
            ws.beta[slot] *= 1.f / q;
        }
        ++ws.vertices[slot];
        ws.pdf_prev[slot] = pdf;
        ws.specular_prev[slot] = delta;
        ws.rough[slot] |= uint8_t(!delta);
        ws.p_prev[slot] = p;
        ws.n_prev[slot] = n;
        ws.next.push(origin, wi, 0.f, kInfinity, slot);
    }

    const RenderContext ctx_;
    const VolPathSettings own_;
    const Mis mis_;
    const uint64_t flight_prefix_;
    const uint64_t wavelength_prefix_;
    const uint64_t subsurface_prefix_;
    std::vector<Material> exits_;  // per Scene::subsurfaces entry
};

}  // namespace

RenderResult render_volpath(const Scene& scene, const RenderSettings& settings,
                            const Intersector& accel, const RenderOptions& opt) {
    const LightSet lights(scene, settings.light_selection, settings.projection_maps);
    const RenderContext ctx{scene, settings, accel, lights, opt.seed};
    const VolPathSettings* own = std::any_cast<VolPathSettings>(&settings.own);
    // A BSSRDF's profile is tabulated per RGB channel: no wavelength can read it.
    if (own && own->spectral && !scene.subsurface_file.empty())
        throw InputError(scene.subsurface_file, scene.subsurface_line,
                         "spectral=\"true\" does not render subsurface materials (their "
                         "profiles are tabulated per RGB channel): render this scene in RGB");
    return render_camera(scene, settings, VolPathIntegrator(ctx, own ? *own : VolPathSettings{}),
                         opt);
}

}  // namespace foton
