#include "photon_integrator.h"

#include <cmath>

#include "engine/core/rng_streams.h"
#include "engine/core/warp.h"
#include "engine/transport/common/direct_control_variate.h"
#include "engine/transport/common/gather_trace.h"
#include "engine/transport/common/next_event.h"
#include "engine/transport/common/shadow_batch.h"
#include "engine/transport/common/surface.h"
#include "engine/transport/common/wavefront.h"

namespace foton {

namespace {
constexpr uint32_t kDimsPerBounce = 8;
// Random dimensions per bounce: delta-or-not choice, lobe (3), light choice, position (2),
// triangle.
constexpr uint32_t kDimChoice = 0, kDimLobe = 1, kDimLight = 4;
// The components (components()).
constexpr uint32_t kPartEmitted = 0, kPartDirect = 1, kPartCaustic = 2, kPartIndirect = 3;
}  // namespace

std::vector<std::string> PhotonIntegrator::components() const {
    const PhotonSettings& ps = ctx_.settings.photon;
    const bool map_alone = ps.mode == PhotonMode::DirectVisualisation && !ps.split_direct;
    return {"emitted", "direct", "caustic", map_alone ? "photon_map" : "indirect"};
}

PhotonIntegrator::PhotonIntegrator(const RenderContext& ctx, const PhotonMaps& maps,
                                   const CacheEvaluator* cache)
    : ctx_(ctx), maps_(maps), cache_(cache) {}

float PhotonIntegrator::rand(uint64_t key, uint32_t depth, uint32_t k) const {
    return rng::uniform(ctx_.seed, kPathStream, key, uint64_t(depth) * kDimsPerBounce + k);
}

void PhotonIntegrator::shade_visible(const ShadingPoint& v, PhotonCameraWorkspace& ws,
                                     std::vector<RGB>& radiance) const {
    const PhotonSettings& ps = ctx_.settings.photon;
    const SurfacePoint& sp = v.sp;
    const Material& m = v.m;
    const warp::Frame& frame = v.frame;
    const Vec3& wo = v.wo;
    const RGB& weight = v.weight;
    const uint32_t slot = v.slot;
    const BsdfContext ctx{sp.front_face, Transport::Radiance};
    // lighting=direct|indirect (the thesis' chapter 7): the visible point's direct light is
    // its light sample, or the direct photons (render_photon leaves the global map with the
    // photons of the chosen kind when it is not split); the rest is indirect.
    const bool direct = ctx_.settings.lighting != Lighting::Indirect;
    const bool indirect = ctx_.settings.lighting != Lighting::Direct;
    if (ps.mode == PhotonMode::DirectVisualisation) {
        // The global map seen directly; when split it holds the indirect light only and the
        // direct light is ray traced (the thesis' comparison of the two).
        if (indirect || !ps.split_direct) {
            const RGB L = weight * maps_.global.radiance(sp.p, frame.s, frame.t, frame.n, m.bsdf,
                                                         wo, ctx, maps_.global_params);
            radiance[slot] += L;
            ws.add_part(slot, kPartIndirect, L);
        }
        if (ps.split_direct && direct) direct_light(v, ws, radiance);
        return;
    }
    if (direct) direct_light(v, ws, radiance);
    if (!indirect) return;
    // Caustics: L S+ D paths, from their own map.
    if (!maps_.caustic.empty()) {
        const RGB L = weight * maps_.caustic.radiance(sp.p, frame.s, frame.t, frame.n, m.bsdf, wo,
                                                      ctx, maps_.caustic_params);
        radiance[slot] += L;
        ws.add_part(slot, kPartCaustic, L);
    }
    // The cache holds irradiance: it serves surfaces whose non-delta part is Lambertian.
    RGB rho;
    if (cache_ && m.bsdf.lambert_albedo(rho)) {
        if (!rho.is_black())
            cache_->queue_lookup(sp, frame, weight * rho * kInvPi, slot,
                                 rng::hash(v.key, v.depth, kCacheStream, 0), ws.path_length[slot],
                                 ws.cache);
        return;
    }
    gather_rays(v, ws);
}

void PhotonIntegrator::direct_light(const ShadingPoint& v, PhotonCameraWorkspace& ws,
                                    std::vector<RGB>& radiance) const {
    const SurfacePoint& sp = v.sp;
    const uint32_t slot = v.slot;
    DirectSample ds;
    LightPick pick;
    const bool sampled =
        sample_direct(ctx_.lights, v, rand(v.key, v.depth, kDimLight),
                      {rand(v.key, v.depth, kDimLight + 1), rand(v.key, v.depth, kDimLight + 2)},
                      rand(v.key, v.depth, kDimLight + 3), ds, &pick);
    if (ctx_.settings.photon.direct_control_variate) {
        // J - g / p now; V g / p by the shadow ray (or the shadow photons) below.
        const RGB term =
            direct_control_term(ctx_.lights, ctx_.scene, v, pick, sampled ? ds.value : RGB{0.f});
        radiance[slot] += term;
        ws.add_part(slot, kPartDirect, term);
    }
    if (!sampled) return;
    const uint32_t li = ds.light;
    // Shadow photons: among the nearest photons of this light, only direct ones mean lit,
    // only shadow ones mean dark; a mix (a penumbra) needs the ray, or, estimated, is lit by
    // the fraction of direct photons.
    int verdict = -1;
    float visibility = 1.f;
    if (!maps_.shadow.empty()) {
        const PhotonMap& lit_map = maps_.direct.empty() ? maps_.global : maps_.direct;
        const float r = 0.5f * maps_.global_params.max_radius;
        uint32_t lit = 0, dark = 0;
        lit_map.for_each_nearest(sp.p, 16, r, [&](uint32_t i) {
            lit += (lit_map.flags(i) & kPhotonDirect) && lit_map.light(i) == li &&
                   dot(lit_map.normal(i), sp.ng) > 0.5f;
        });
        maps_.shadow.for_each_nearest(sp.p, 16, r, [&](uint32_t i) {
            dark += maps_.shadow.light(i) == li && dot(maps_.shadow.normal(i), sp.ng) > 0.5f;
        });
        if (lit > 0 && dark == 0) verdict = 1;
        if (dark > 0 && lit == 0) verdict = 0;
        if (lit > 0 && dark > 0 && ctx_.settings.photon.shadow_estimate) {
            verdict = 1;
            visibility = float(lit) / float(lit + dark);
        }
    }
    if (verdict >= 0) {
        ++ws.saved;
        if (verdict == 1) {
            radiance[slot] += ds.value * visibility;
            ws.add_part(slot, kPartDirect, ds.value * visibility);
        }
        return;
    }
    queue_direct(ds, slot, ws.shadow, ws.shadow_value);
}

void PhotonIntegrator::gather_rays(const ShadingPoint& v, PhotonCameraWorkspace& ws) const {
    const PhotonSettings& ps = ctx_.settings.photon;
    const SurfacePoint& sp = v.sp;
    const Material& m = v.m;
    const warp::Frame& frame = v.frame;
    const Vec3& wo = v.wo;
    const uint32_t n = ps.gather_rays;
    if (n == 0 || maps_.global.empty()) return;
    const BsdfContext ctx{sp.front_face, Transport::Radiance};
    const uint64_t key = rng::hash(v.key, v.depth, kPhotonGatherStream, 0);
    // Guided gathering on diffuse surfaces: the histogram of the indirect photons here (the
    // direct ones point at the lights, whose emission the gather hits do not count).
    bool guided = false;
    if (ps.guided_gather && !(m.bsdf.flags() & kGlossy)) {
        ws.guide.clear();
        EstimateParams gp = maps_.global_params;
        gp.k = ps.guide_photons;
        maps_.global.for_each_estimate_photon(sp.p, sp.ng, gp, [&](uint32_t i) {
            if (maps_.global.flags(i) & kPhotonDirect) return;
            ws.guide.add(frame.to_local(maps_.global.incident(i)),
                         maps_.global.power(i).luminance());
        });
        // A third of the density is spread evenly (defensive sampling): a histogram of a few
        // hundred photons is noisy, and where indirect light is broad (the Cornell box) a
        // sharper guide loses to plain cosine sampling.
        guided = ws.guide.finish(0.5f);
    }
    for (uint32_t g = 0; g < n; ++g) {
        const Point2 u = sample_pattern(SamplerKind::Jittered, g, n, ctx_.seed, key);
        Vec3 wl;
        RGB f;
        float pdf;
        if (guided) {
            wl = ws.guide.sample(u, pdf);
            f = m.bsdf.f_restricted(wo, wl, ctx, kDiffuse | kGlossy);
        } else {
            BsdfSample bs;
            if (!m.bsdf.sample(wo, rng::uniform(ctx_.seed, key, g, 2), u, ctx, bs,
                               kDiffuse | kGlossy))
                continue;
            // The restricted sample is over the non-delta lobes only; its weight is theirs.
            wl = bs.wi;
            f = bs.f;
            pdf = bs.pdf;
        }
        if (!(pdf > 0.f)) continue;
        const Vec3 wi = frame.to_world(wl);
        if (!m.bsdf.side_allowed(wi, sp.ng)) continue;
        const RGB w = v.weight * f * (std::fabs(wl.z) / (pdf * float(n)));
        if (w.is_black()) continue;
        ws.gather.push(offset_origin(sp, wi), wi, kInfinity, v.slot, w);
    }
}

RGB PhotonIntegrator::photon_radiance(const SurfacePoint& sp, const Material& m,
                                      const Vec3& d) const {
    const warp::Frame frame = sp.frame();
    const Vec3 wo = frame.to_local(-d);
    const BsdfContext ctx{sp.front_face, Transport::Radiance};
    RGB sum;
    for (const PhotonMap* map : {&maps_.global, &maps_.direct}) {
        if (map->empty()) continue;
        // Lambertian surfaces read Christensen's precomputed irradiance when there is one
        // nearby with a similar normal; anything else takes a full estimate.
        RGB rho, e;
        if (map->has_precomputed() && m.bsdf.lambert_albedo(rho) &&
            map->lookup_irradiance(sp.p, sp.ng, maps_.global_params.max_radius, e))
            sum += rho * e * kInvPi;
        else
            sum += map->radiance(sp.p, frame.s, frame.t, frame.n, m.bsdf, wo, ctx,
                                 maps_.global_params);
    }
    return sum;
}

void PhotonIntegrator::final_gather(PhotonCameraWorkspace& ws, std::vector<RGB>& radiance,
                                    RenderStats& stats) const {
    StageClock clock;
    FinalGatherBatch& b = ws.batch;
    b.hits.clear();
    b.order.clear();
    b.values.clear();
    // Emission is not counted at the hits: direct light came from NEE, and light through
    // specular surfaces from the caustic map.
    const std::size_t rays = trace_gather(
        ctx_.scene, ctx_.accel, ws.gather, nullptr, stats,
        [&](uint32_t slot, const RGB& w, const SurfacePoint& sp, const Material& m, const Vec3& d) {
            b.order.emplace_back(slot, int32_t(b.hits.size()));
            b.hits.push_back({sp, &m, d, w});
        },
        [&](uint32_t slot, const RGB& v) {
            b.order.emplace_back(slot, -1 - int32_t(b.values.size()));
            b.values.push_back(v);
        });
    stats.secondary_rays += rays;
    stats.add(Stage::FinalGather, rays, clock);
    photon_radiance_batch(b);
    for (const auto& [slot, i] : b.order) {
        const RGB L =
            i >= 0 ? b.hits[std::size_t(i)].w * b.L[std::size_t(i)] : b.values[std::size_t(-1 - i)];
        radiance[slot] += L;
        ws.add_part(slot, kPartIndirect, L);
    }
    stats.add(Stage::PhotonEstimate, b.hits.size(), clock);
}

void PhotonIntegrator::trace_phase(uint32_t phase, const std::vector<SampleJob>& jobs,
                                   IntegratorWorkspace& base, std::vector<RGB>& radiance,
                                   RenderStats& stats) const {
    PhotonCameraWorkspace& ws = static_cast<PhotonCameraWorkspace&>(base);
    if (phase == 1) {
        final_gather(ws, radiance, stats);
        if (cache_)
            ws.as_part(kPartIndirect, radiance,
                       [&] { cache_->resolve(ws.cache, radiance, stats); });
        return;
    }
    StageClock clock;
    const std::size_t n = jobs.size();
    radiance.assign(n, RGB{0.f});
    ws.beta.assign(n, RGB{1.f});
    ws.rays.clear();
    ws.shadow.clear();
    ws.shadow_value.clear();
    ws.gather.clear();
    ws.path_length.assign(n, 0.f);
    if (cache_) ws.cache.begin(cache_->levels(), cache_->bounds(), cache_->params());
    generate_camera_rays(ctx_.scene, ctx_.settings.sampler, jobs, ctx_.seed, ws.rays);
    stats.camera_rays += n;
    stats.add(Stage::Generate, n, clock);

    // Camera rays through specular chains to the visible points.
    run_wavefront(
        ctx_.accel, ws.rays, ws.next, ws.hits, 0, std::numeric_limits<uint32_t>::max(), stats,
        clock,
        [&](uint32_t depth) {
            for (std::size_t i = 0; i < ws.rays.size(); ++i) {
                const uint32_t slot = ws.rays.id[i];
                const SampleJob& job = jobs[slot];
                RGB& beta = ws.beta[slot];
                const uint32_t geom = ws.hits.geom[i];
                if (geom == kNoHit) {
                    if (ctx_.settings.lighting != Lighting::Indirect) {
                        const RGB L = beta * ctx_.scene.background_along(ws.rays.origin(i),
                                                                         ws.rays.direction(i));
                        radiance[slot] += L;
                        ws.add_part(slot, kPartEmitted, L);
                    }
                    continue;
                }
                const Vec3 d = ws.rays.direction(i);
                ws.path_length[slot] += ws.hits.t[i];
                const SurfacePoint sp = surface_at(ctx_.scene, ws.rays, ws.hits, i);
                std::optional<Material> scratch;
                const Material& m = ctx_.scene.material_at(geom, sp.tex(), scratch);
                // Emitters seen from the camera or through specular chains (L S* E paths have no
                // diffuse vertex, so no photon estimate holds them).
                if (m.emits_towards(sp.front_face) &&
                    ctx_.settings.lighting != Lighting::Indirect) {
                    radiance[slot] += beta * m.emission;
                    ws.add_part(slot, kPartEmitted, beta * m.emission);
                }
                if (m.bsdf.empty()) continue;
                const float p_delta = m.bsdf.selection_probability(kSpecular);
                if (m.bsdf.has_delta() && rand(job.id, depth, kDimChoice) < p_delta) {
                    if (depth >= ctx_.settings.max_depth) continue;
                    const warp::Frame frame = sp.frame();
                    const Vec3 wo = frame.to_local(-d);
                    const BsdfContext ctx{sp.front_face, Transport::Radiance};
                    BsdfSample bs;
                    if (!m.bsdf.sample(
                            wo, rand(job.id, depth, kDimLobe),
                            {rand(job.id, depth, kDimLobe + 1), rand(job.id, depth, kDimLobe + 2)},
                            ctx, bs, kSpecular))
                        continue;
                    const Vec3 wi = frame.to_world(bs.wi);
                    const float side = dot(wi, sp.ng);
                    if ((bs.flags & kTransmission) ? side >= 0.f : side <= 0.f) continue;
                    beta *= bs.f * (std::fabs(bs.wi.z) / (bs.pdf * p_delta));
                    ws.next.push(offset_origin(sp, wi), wi, 0.f, kInfinity, slot);
                    continue;
                }
                const RGB w = m.bsdf.has_delta() ? beta * (1.f / (1.f - p_delta)) : beta;
                shade_visible(ShadingPoint(sp, m, d, w, slot, depth, job.id), ws, radiance);
            }
        },
        // The bounce's cache lookups, served as a batch once it is shaded.
        [&](uint32_t) {
            if (cache_)
                ws.as_part(kPartIndirect, radiance,
                           [&] { cache_->serve_lookups(ws.cache, radiance, stats, clock); });
        });
    stats.shadow_rays_saved += ws.saved;
    ws.saved = 0;
    ws.as_part(kPartDirect, radiance, [&] {
        resolve_shadow_rays(ctx_.accel, ws.shadow, ws.shadow_value, ws.occluded, radiance, stats,
                            clock);
    });
}

}  // namespace foton
