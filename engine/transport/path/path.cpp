#include "path.h"

#include <cmath>

#include "engine/core/rng_streams.h"
#include "engine/core/warp.h"
#include "engine/transport/common/mis.h"
#include "engine/transport/common/next_event.h"
#include "engine/transport/common/path_sampler.h"
#include "engine/transport/common/shadow_batch.h"
#include "engine/transport/common/surface.h"
#include "engine/transport/common/wavefront.h"
#include "engine/transport/irradiance_cache/cache_render.h"
#include "engine/transport/run/camera_driver.h"
#include "path_guide.h"

namespace foton {

namespace {
// Random dimensions per bounce (path_sampler.h). The distributed tracer's shadow samples use
// their own keyed streams.
constexpr uint32_t kDimLightSelect = kPathDimLightSelect, kDimLight = kPathDimLight,
                   kDimBsdf = kPathDimBsdf, kDimRoulette = kPathDimRoulette;
}  // namespace

PathIntegrator::PathIntegrator(const RenderContext& ctx, const VertexRules& rules,
                               const PathReaders& readers)
    : ctx_(ctx),
      rules_(rules),
      cache_(readers.cache),
      guide_(readers.guide),
      kernels_(kernel_materials()) {}

float PathIntegrator::rand(const PathWorkspace& ws, uint32_t slot, uint32_t depth,
                           uint32_t k) const {
    return ws.samplers[slot].get1(ctx_.seed, depth, k);
}

Point2 PathIntegrator::rand2(const PathWorkspace& ws, uint32_t slot, uint32_t depth,
                             uint32_t k) const {
    return ws.samplers[slot].get2(ctx_.seed, depth, k);
}

bool PathIntegrator::shade_cached(uint32_t depth, const SurfacePoint& sp, const Material& m,
                                  const Vec3& d, uint32_t slot, PathWorkspace& ws) const {
    RGB rho;
    if (!m.bsdf.has_non_delta() || !m.bsdf.lambert_albedo(rho)) return false;
    const uint64_t key = ws.keys[slot];
    const warp::Frame frame = sp.frame();
    const Vec3 wo = frame.to_local(-d);
    RGB& beta = ws.beta[slot];
    const auto vertex = [&] { return ShadingPoint(sp, m, d, beta, slot, depth, key); };
    // A material with delta lobes too: the delta part continues the path, the diffuse part
    // stops here, each chosen with its lobes' probability and weighted by its inverse.
    if (m.bsdf.has_delta()) {
        const float p_delta = m.bsdf.selection_probability(kSpecular);
        if (rng::uniform(ctx_.seed, kCacheVertexChoiceStream, key, depth) < p_delta) {
            const BsdfContext ctx{sp.front_face, Transport::Radiance};
            BsdfSample bs;
            if (!m.bsdf.sample(wo, rand(ws, slot, depth, kDimBsdf),
                               rand2(ws, slot, depth, kDimBsdf + 1), ctx, bs, kSpecular))
                return true;
            const Vec3 wi = frame.to_world(bs.wi);
            const float side = dot(wi, sp.ng);
            if ((bs.flags & kTransmission) ? side >= 0.f : side <= 0.f) return true;
            beta *= bs.f * (std::fabs(bs.wi.z) / (bs.pdf * p_delta));
            ws.eta_scale[slot] *= bs.eta * bs.eta;
            ws.specular_prev[slot] = 1;
            ws.p_prev[slot] = sp.p;
            ws.n_prev[slot] = sp.ng;
            ws.next.push(offset_origin(sp, wi), wi, 0.f, kInfinity, slot);
            return true;
        }
        beta *= 1.f / (1.f - p_delta);
    }
    // No BSDF sample leaves this vertex, so the light sample is the only estimator of its
    // direct light and takes full weight.
    DirectSample ds;
    if (sample_direct(ctx_.lights, vertex(), rand(ws, slot, depth, kDimLightSelect),
                      rand2(ws, slot, depth, kDimLight), rand(ws, slot, depth, kDimLight + 2), ds))
        queue_direct(ds, slot, ws.shadow, ws.shadow_value);
    if (!rho.is_black())
        cache_->queue_lookup(sp, frame, beta * rho * kInvPi, slot,
                             rng::hash(key, depth, kCacheStream, 0), ws.path_length[slot],
                             ws.cache);
    return true;
}

void PathIntegrator::shade(uint32_t depth, PathWorkspace& ws, std::vector<RGB>& radiance) const {
    ws.next.clear();
    ws.shadow.clear();
    ws.shadow_value.clear();
    // The hits the SIMD kernels take (Lambertian and specular vertices, path_lanes.cpp) are
    // grouped by kernel and shaded together; every other hit is shaded here, one at a time.
    const bool kernels = kernels_.enabled && depth < ctx_.settings.max_depth;
    ws.diffuse_entries.clear();
    ws.specular_entries.clear();
    for (std::vector<uint32_t>& g : ws.diffuse_groups) g.clear();
    for (std::size_t i = 0; i < ws.rays.size(); ++i) {
        switch (kernels ? kernel_of(ws, i) : KernelKind::None) {
            case KernelKind::Diffuse:
                ws.diffuse_groups[kernels_.object_group[ws.hits.geom[i]]].push_back(uint32_t(i));
                break;
            case KernelKind::Specular:
                ws.specular_entries.push_back(uint32_t(i));
                break;
            case KernelKind::None:
                shade_vertex(depth, i, ws, radiance);
                break;
        }
    }
    // Each glossy kind's lanes together (the order of lanes changes no path's result).
    for (const std::vector<uint32_t>& g : ws.diffuse_groups)
        ws.diffuse_entries.insert(ws.diffuse_entries.end(), g.begin(), g.end());
    shade_lanes(depth, KernelKind::Diffuse, ws);
    shade_lanes(depth, KernelKind::Specular, ws);
}

void PathIntegrator::shade_vertex(uint32_t depth, std::size_t i, PathWorkspace& ws,
                                  std::vector<RGB>& radiance) const {
    const RenderSettings& rs = ctx_.settings;
    const bool guided = guide_ && !guide_->empty() && rules_.guided;
    const bool nee = rules_.nee;
    const Mis mis = rules_.mis;
    const uint32_t slot = ws.rays.id[i];
    const uint64_t key = ws.keys[slot];
    RGB& beta = ws.beta[slot];
    const uint32_t geom = ws.hits.geom[i];
    const Vec3 d = ws.rays.direction(i);
    // Emission found by this ray, weighted against having sampled it as a light (whose
    // density, selection included, `light_pdf` gives).
    const bool counts_emission = !(ws.first_depth > 0 && depth == ws.first_depth);
    auto emission_weight = [&](auto&& light_pdf) {
        if (depth == 0 || ws.specular_prev[slot] || !nee || rules_.emission_whole) return 1.f;
        if (mis.heuristic == MisHeuristic::None) return 0.f;
        return mis_weight_bsdf(mis, ws.pdf_prev[slot], light_pdf());
    };
    // lighting=direct|indirect: light reached after this many non-specular vertices.
    const bool counts_light = counts(rs.lighting, ws.nondelta[slot]);
    if (geom == kNoHit) {
        if (!counts_light) return;
        if (!ctx_.scene.environment)
            radiance[slot] += beta * ctx_.scene.background;
        else if (counts_emission)
            radiance[slot] +=
                beta * ctx_.scene.environment->Le(ws.rays.origin(i), d) * emission_weight([&] {
                    return ctx_.lights.nee_environment_pdf(ws.rays.origin(i), d);
                });
        return;
    }
    const SurfacePoint sp = surface_at(ctx_.scene, ws.rays, ws.hits, i);
    std::optional<Material> scratch;
    const Material& seen = ctx_.scene.material_at(geom, sp.tex(), scratch);
    // regularize: after the first non-specular vertex, near-specular lobes roughen.
    const Material& m =
        rs.regularize && ws.nondelta[slot] > 0 ? regularized_material(seen, scratch) : seen;
    ws.path_length[slot] += ws.hits.t[i];

    if (m.emits_towards(sp.front_face) && counts_emission && counts_light) {
        const float w = emission_weight([&] {
            const int li = ctx_.lights.emitter_of(geom);
            return li < 0 ? 0.f
                          : ctx_.lights.nee_pdf(uint32_t(li), ws.hits.prim[i], ws.p_prev[slot],
                                                ws.n_prev[slot], sp.p, sp.ng);
        });
        radiance[slot] += beta * m.emission * w;
    }
    if (depth >= rs.max_depth || m.bsdf.empty()) return;
    // Direct light only: once a second non-specular vertex is behind, nothing counts.
    if (rs.lighting == Lighting::Direct && ws.nondelta[slot] >= 2) return;
    if (cache_ && ws.chain_specular[slot] && shade_cached(depth, sp, m, d, slot, ws)) return;

    const ShadingPoint v(sp, m, d, beta, slot, depth, key);
    const warp::Frame& frame = v.frame;
    const Vec3& wo = v.wo;
    const BsdfContext ctx{sp.front_face, Transport::Radiance};

    if (rules_.ambient) {
        const RGB ambient = ctx_.scene.ambient.radiance();
        const RGB amb = m.type == MaterialType::Generic ? m.base_color * m.c_diffuse
                                                        : m.base_color * m.c_ambient;
        radiance[slot] += beta * amb * ambient;
    }

    // A guided vertex's BSDF strategy is a mixture with its bin's direction histogram.
    GuideMixture strategy;
    if (guided && guidable(m.bsdf)) {
        const int bin = guide_->find(sp.p, sp.ng);
        if (bin >= 0) strategy = guide_->mixture(bin, rs.guide.fraction);
    }

    // Next event estimation.
    if (nee && m.bsdf.has_non_delta() && !ctx_.lights.empty() &&
        counts(rs.lighting, ws.nondelta[slot] + 1u)) {
        auto estimate = [&](uint32_t li, float pick_pdf, uint32_t tri, Point2 u, float uc,
                            float scale) {
            // The distributed tracer's glossy lobes see area lights by being sampled.
            const uint8_t lobes = rules_.glossy_by_sampling && !ctx_.lights.emitter(li).is_delta()
                                      ? uint8_t(kDiffuse)
                                      : uint8_t(kDiffuse | kGlossy);
            DirectSample ds;
            if (sample_light(ctx_.lights, {li, pick_pdf, u, uc, tri}, v, lobes, mis, scale, ds,
                             strategy))
                queue_direct(ds, slot, ws.shadow, ws.shadow_value);
        };
        if (rules_.every_light) {
            const uint32_t n = rs.light_samples;
            for (uint32_t li = 0; li < ctx_.lights.size(); ++li) {
                const uint32_t k = ctx_.lights.emitter(li).is_delta() ? 1 : n;
                for (uint32_t s = 0; s < k; ++s) {
                    const uint64_t lkey = rng::hash(key, depth, li, 0);
                    const Point2 u = sample_pattern(SamplerKind::Jittered, s, k, ctx_.seed, lkey);
                    const float uc = rng::uniform(ctx_.seed, lkey, s, 2);
                    estimate(li, 1.f, kWholeEmitter, u, uc, 1.f / float(k));
                }
            }
        } else {
            LightPick pick;
            if (ctx_.lights.pick(rand(ws, slot, depth, kDimLightSelect), sp.p, sp.ng, pick))
                estimate(pick.light, pick.pmf, pick.tri, rand2(ws, slot, depth, kDimLight),
                         rand(ws, slot, depth, kDimLight + 2), 1.f);
        }
    }

    // Continue the path by sampling the BSDF.
    BsdfSample bs;
    const uint8_t only = rules_.continue_lobes;
    const float u_lobe = rand(ws, slot, depth, kDimBsdf);
    const Point2 u_dir = rand2(ws, slot, depth, kDimBsdf + 1);
    float bsdf_pdf = 0.f;
    if (strategy.active()
            ? !sample_mixture(m.bsdf, wo, frame, ctx, strategy, u_lobe, u_dir, bs, bsdf_pdf)
            : !m.bsdf.sample(wo, u_lobe, u_dir, ctx, bs, only))
        return;
    const Vec3 wi = frame.to_world(bs.wi);
    // A direction on the wrong side of the true surface would leak light through it.
    const float side = dot(wi, sp.ng);
    if ((bs.flags & kTransmission) ? side >= 0.f : side <= 0.f) return;
    // What roulette weighs: the throughput as BSDF sampling would carry it. A guided
    // direction's weight is low exactly because light is likely to come from there; a
    // roulette on it would kill the paths the guide sent towards the light.
    beta *= bs.f * (std::fabs(bs.wi.z) / bs.pdf);
    const RGB rr_beta = strategy.active() && bsdf_pdf > 0.f ? beta * (bs.pdf / bsdf_pdf) : beta;
    if (beta.is_black()) return;
    ws.eta_scale[slot] *= bs.eta * bs.eta;
    // Russian roulette: survive with the path's weight, capped at 1, and reweight. Inside
    // glass beta is 1/eta^2 of the carried throughput, and the path leaves with it back;
    // deciding on beta alone would kill paths through glass (caustics) 2.25x too often.
    if (depth + 1 >= rs.rr_depth) {
        const float q = std::min(1.f, rr_beta.max_component() * ws.eta_scale[slot]);
        if (rand(ws, slot, depth, kDimRoulette) >= q) return;
        beta *= 1.f / q;
    }
    ws.pdf_prev[slot] = bs.pdf;
    ws.specular_prev[slot] = bs.is_delta();
    // A specular bounce after the first non-specular vertex makes what it finds a
    // caustic there: indirect light, as the photon maps count it.
    if (!bs.is_delta() || ws.nondelta[slot] == 1)
        ws.nondelta[slot] = uint8_t(std::min(2, ws.nondelta[slot] + 1));
    ws.chain_specular[slot] &= uint8_t(bs.is_delta());
    ws.p_prev[slot] = sp.p;
    ws.n_prev[slot] = sp.ng;
    ws.next.push(offset_origin(sp, wi), wi, 0.f, kInfinity, slot);
}

void PathIntegrator::run(PathWorkspace& ws, std::vector<RGB>& radiance, float* first_dist,
                         RenderStats& stats, StageClock& clock) const {
    run_wavefront(
        ctx_.accel, ws.rays, ws.next, ws.hits, ws.first_depth, std::numeric_limits<uint32_t>::max(),
        stats, clock,
        [&](uint32_t depth) {
            if (first_dist && depth == ws.first_depth)
                for (std::size_t i = 0; i < ws.rays.size(); ++i)
                    first_dist[ws.rays.id[i]] =
                        ws.hits.geom[i] == kNoHit ? kInfinity : ws.hits.t[i];
            shade(depth, ws, radiance);
        },
        [&](uint32_t) {
            // The bounce's cache lookups before its shadow rays, as when they were made one
            // by one during shading.
            if (cache_) cache_->serve_lookups(ws.cache, radiance, stats, clock);
            resolve_shadow_rays(ctx_.accel, ws.shadow, ws.shadow_value, ws.occluded, radiance,
                                stats, clock);
        });
}

void PathIntegrator::trace_phase(uint32_t /*phase*/, const std::vector<SampleJob>& jobs,
                                 IntegratorWorkspace& base, std::vector<RGB>& radiance,
                                 RenderStats& stats) const {
    PathWorkspace& ws = static_cast<PathWorkspace&>(base);
    StageClock clock;
    const std::size_t n = jobs.size();
    ws.keys.resize(n);
    for (std::size_t i = 0; i < n; ++i) ws.keys[i] = jobs[i].id;
    ws.samplers.resize(n);
    for (std::size_t i = 0; i < n; ++i)
        ws.samplers[i] =
            PathSampler::for_job(ctx_.settings.sampler, ctx_.scene, jobs[i], ctx_.seed);
    ws.rays.clear();
    generate_camera_rays(ctx_.scene, ctx_.settings.sampler, jobs, ctx_.seed, ws.rays);
    start_camera_paths(ws, radiance, stats, clock);
}

void PathIntegrator::trace_camera_paths(RayBatch& rays, std::vector<PathSampler>& samplers,
                                        std::vector<uint64_t>& keys, IntegratorWorkspace& base,
                                        std::vector<RGB>& radiance, RenderStats& stats) const {
    PathWorkspace& ws = static_cast<PathWorkspace&>(base);
    StageClock clock;
    std::swap(ws.keys, keys);
    std::swap(ws.samplers, samplers);
    std::swap(ws.rays, rays);
    start_camera_paths(ws, radiance, stats, clock);
}

void PathIntegrator::start_camera_paths(PathWorkspace& ws, std::vector<RGB>& radiance,
                                        RenderStats& stats, StageClock& clock) const {
    const std::size_t n = ws.rays.size();
    radiance.assign(n, RGB{0.f});
    ws.beta.assign(n, RGB{1.f});
    ws.eta_scale.assign(n, 1.f);
    ws.pdf_prev.assign(n, 0.f);
    ws.specular_prev.assign(n, 1);
    ws.chain_specular.assign(n, 1);
    ws.nondelta.assign(n, 0);
    ws.p_prev.assign(n, Vec3{});
    ws.n_prev.assign(n, Vec3{});
    ws.path_length.assign(n, 0.f);
    ws.first_depth = 0;
    if (cache_) ws.cache.begin(cache_->levels(), cache_->bounds(), cache_->params());
    stats.camera_rays += n;
    stats.add(Stage::Generate, n, clock);
    run(ws, radiance, nullptr, stats, clock);
    if (cache_) cache_->resolve(ws.cache, radiance, stats);
}

void PathIntegrator::radiance_along(const RayBatch& rays, const std::vector<uint64_t>& keys,
                                    IntegratorWorkspace& base, std::vector<RGB>& radiance,
                                    float* first_dist, RenderStats& stats) const {
    PathWorkspace& ws = static_cast<PathWorkspace&>(base);
    StageClock clock;
    ws.keys = keys;
    const std::size_t n = radiance.size();
    ws.samplers.resize(n);
    for (std::size_t i = 0; i < n; ++i) ws.samplers[i] = PathSampler::uniform(keys[i], ctx_.seed);
    ws.beta.assign(n, RGB{1.f});
    ws.eta_scale.assign(n, 1.f);
    ws.pdf_prev.assign(n, 0.f);
    ws.specular_prev.assign(n, 0);
    ws.chain_specular.assign(n, 0);  // the cache is not consulted again on the way
    ws.nondelta.assign(n, 1);        // the rays leave a scattering vertex
    ws.p_prev.assign(n, Vec3{});
    ws.n_prev.assign(n, Vec3{});
    ws.path_length.assign(n, 0.f);
    ws.first_depth = 1;
    ws.rays = rays;
    run(ws, radiance, first_dist, stats, clock);
}

std::unique_ptr<RadianceAlongRays> make_path_onwards(const RenderContext& ctx) {
    return std::make_unique<PathIntegrator>(ctx, VertexRules::path(ctx.settings));
}

RenderResult render_path(const Scene& scene, const RenderSettings& settings,
                         const Intersector& accel, const RenderOptions& opt) {
    const LightSet lights(scene, settings.light_selection, settings.projection_maps);
    const RenderContext ctx{scene, settings, accel, lights, opt.seed};
    if (settings.guide.enabled) return render_guided_path(ctx, opt);
    if (settings.indirect != IndirectMode::IrradianceCache)
        return render_camera(scene, settings, PathIntegrator(ctx, VertexRules::path(settings)),
                             opt);
    // The cache's records trace on with a path tracer that does not read the cache.
    const PathIntegrator onwards(ctx, VertexRules::path(settings));
    CacheClient client;
    client.camera = [&](const CacheEvaluator& cache) -> std::unique_ptr<CameraIntegrator> {
        return std::make_unique<PathIntegrator>(ctx, VertexRules::path(settings),
                                                PathReaders{&cache, nullptr});
    };
    client.onwards = &onwards;
    StageGraph graph;
    graph.set_progress(opt.progress);
    RenderResult result = render_with_cache(ctx, client, opt, graph, {});
    result.stats.graph = graph.report();
    return result;
}

RenderResult render_distributed(const Scene& scene, const RenderSettings& settings,
                                const Intersector& accel, const RenderOptions& opt) {
    const LightSet lights(scene, LightSelection::Power, settings.projection_maps);
    const RenderContext ctx{scene, settings, accel, lights, opt.seed};
    return render_camera(scene, settings, PathIntegrator(ctx, VertexRules::distributed()), opt);
}

}  // namespace foton
