#include "photon_integrator.h"

#include <cmath>

#include "engine/core/warp.h"
#include "shadow_batch.h"
#include "surface.h"

namespace foton {

namespace {
constexpr uint32_t kDimsPerBounce = 8;
// Random dimensions per bounce: delta-or-not choice, lobe (3), light choice, position (2),
// triangle.
constexpr uint32_t kDimChoice = 0, kDimLobe = 1, kDimLight = 4;
// Specular bounces a final-gather ray may take before it must find a diffuse surface.
constexpr uint32_t kGatherSpecularDepth = 4;
}  // namespace

PhotonIntegrator::PhotonIntegrator(const Scene& scene, const Intersector& accel,
                                   const LightSet& lights, const PhotonMaps& maps, uint64_t seed)
    : scene_(scene),
      accel_(accel),
      lights_(lights),
      maps_(maps),
      seed_(seed),
      strata_(HemisphereStrata::from_count(scene.render.cache.samples)) {}

float PhotonIntegrator::rand(const SampleJob& j, uint32_t depth, uint32_t k) const {
    return rng::uniform(seed_, kPathStream, j.id, uint64_t(depth) * kDimsPerBounce + k);
}

void PhotonIntegrator::shade_visible(const SurfacePoint& sp, const Material& m, const Vec3& d,
                                     const RGB& weight, uint32_t slot, const SampleJob& job,
                                     uint32_t depth, PhotonCameraWorkspace& ws,
                                     std::vector<RGB>& radiance) const {
    const PhotonSettings& ps = scene_.render.photon;
    const warp::Frame frame(sp.ns);
    const Vec3 wo = frame.to_local(-d);
    const BsdfContext ctx{sp.front_face, Transport::Radiance};
    if (ps.mode == PhotonMode::DirectVisualisation) {
        // The global map seen directly; when split it holds the indirect light only and the
        // direct light is ray traced (the thesis' comparison of the two).
        radiance[slot] += weight * maps_.global.radiance(sp.p, frame.s, frame.t, frame.n, m.bsdf,
                                                         wo, ctx, maps_.global_params);
        if (ps.split_direct) direct_light(sp, m, wo, frame, weight, slot, job, depth, ws, radiance);
        return;
    }
    // Caustics: L S+ D paths, from their own map.
    if (!maps_.caustic.empty())
        radiance[slot] += weight * maps_.caustic.radiance(sp.p, frame.s, frame.t, frame.n, m.bsdf,
                                                          wo, ctx, maps_.caustic_params);
    direct_light(sp, m, wo, frame, weight, slot, job, depth, ws, radiance);
    // The cache holds irradiance: it serves surfaces whose non-delta part is Lambertian.
    RGB rho;
    if (cache_ && m.bsdf.lambert_albedo(rho)) {
        if (!rho.is_black())
            cache_indirect(sp, frame, weight * rho * kInvPi, slot, job, depth, ws, radiance);
        return;
    }
    gather_rays(sp, m, wo, frame, weight, slot, job, depth, ws);
}

void PhotonIntegrator::cache_indirect(const SurfacePoint& sp, const warp::Frame& frame,
                                      const RGB& weight, uint32_t slot, const SampleJob& job,
                                      uint32_t depth, PhotonCameraWorkspace& ws,
                                      std::vector<RGB>& radiance) const {
    const CacheSettings& cs = scene_.render.cache;
    // The notes' edge case: a record beyond an edge that p cannot see must not be used.
    // Both ends are lifted off their surfaces by a tenth of their distance, so that the
    // segment clears a curved surface between them (a chord of a sphere of radius R dips
    // d^2 / 8R below it) while a wall between them still blocks it.
    auto visible = [&](const IrradianceRecord& r) {
        if (!cs.visibility) return true;
        const float gap = length(r.p - sp.p);
        if (!(gap > sp.epsilon)) return true;
        const float lift = std::max(sp.epsilon, 0.1f * gap);
        const Vec3 a = sp.p + sp.ng * lift;
        const Vec3 b = r.p + r.n * lift;
        const Vec3 d = b - a;
        const float len = length(d);
        const Vec3 u = d * (1.f / len);
        ++ws.lookup.visibility_tests;
        if (accel_.occluded1({a.x, a.y, a.z, u.x, u.y, u.z, 0.f, len}, ws.cache_trace)) {
            ++ws.lookup.visibility_rejections;
            return false;
        }
        return true;
    };
    RGB e;
    if (cache_->interpolate(sp.p, frame.n, e, visible, ws.lookup)) {
        radiance[slot] += weight * e;
        return;
    }
    // A new record here: M x N stratified rays; those below the geometric surface see
    // nothing (their radiance stays 0, their distance infinite).
    CacheRequest q;
    q.p = sp.p;
    q.s = frame.s;
    q.t = frame.t;
    q.n = frame.n;
    q.r_min = cs.r_min_pixels * scene_.camera.footprint(ws.path_length[slot]);
    q.slot = slot;
    q.weight = weight;
    q.first = uint32_t(ws.cache_L.size());
    q.key = rng::hash(job.id, depth, 0x1cac, 0);
    const uint32_t count = strata_.count();
    ws.cache_L.resize(ws.cache_L.size() + count, RGB{0.f});
    ws.cache_dist.resize(ws.cache_dist.size() + count, kInfinity);
    const uint64_t key = q.key;
    for (uint32_t j = 0; j < strata_.m; ++j)
        for (uint32_t k = 0; k < strata_.n; ++k) {
            const uint32_t i = j * strata_.n + k;
            const Vec3 wi = frame.to_world(strata_.direction(
                j, k, {rng::uniform(seed_, key, i, 0), rng::uniform(seed_, key, i, 1)}));
            if (dot(wi, sp.ng) <= 0.f) continue;
            ws.cache_rays.push(offset_origin(sp, wi), wi, 0.f, kInfinity, q.first + i);
        }
    ws.requests.push_back(q);
}

void PhotonIntegrator::compute_records(PhotonCameraWorkspace& ws, std::vector<RGB>& radiance,
                                       RenderStats& stats) const {
    if (ws.requests.empty()) return;
    const CacheSettings& cs = scene_.render.cache;
    std::swap(ws.gather, ws.cache_rays);
    ws.cache_rays.clear();
    ws.gather_weight.assign(ws.gather.size(), RGB{1.f});
    // The rays' time and counts go to the final-gather (or intersect and occlusion) stages;
    // the cache-record stage is the records' own arithmetic.
    if (cs.secondary == CacheSecondary::Photon) {
        final_gather(ws, ws.cache_L, ws.cache_dist.data(), stats);
    } else {
        // Direct light only: one light sample at each first hit.
        StageClock clock;
        accel_.intersect(ws.gather, ws.hits, stats.trace);
        stats.stage_items[int(Stage::Intersect)] += ws.gather.size();
        stats.stage_seconds[int(Stage::Intersect)] += clock.lap();
        ws.shadow.clear();
        ws.shadow_value.clear();
        for (std::size_t i = 0; i < ws.gather.size(); ++i) {
            const uint32_t id = ws.gather.id[i];
            const uint32_t geom = ws.hits.geom[i];
            if (geom == kNoHit) continue;
            ws.cache_dist[id] = ws.hits.t[i];
            const SurfacePoint sp = surface_at(scene_, ws.gather, ws.hits, i);
            const Material& m = scene_.materials[scene_.objects[geom].material];
            if (!m.bsdf.has_non_delta()) continue;
            const warp::Frame frame(sp.ns);
            const Vec3 wo = frame.to_local(-ws.gather.direction(i));
            SampleJob pseudo;
            pseudo.id =
                rng::hash(ws.requests[id / strata_.count()].key, id % strata_.count(), 0x5ec0, 0);
            direct_light(sp, m, wo, frame, RGB{1.f}, id, pseudo, 0, ws, ws.cache_L);
        }
        stats.stage_items[int(Stage::Shade)] += ws.gather.size();
        stats.stage_seconds[int(Stage::Shade)] += clock.lap();
        resolve_shadow_rays(accel_, ws.shadow, ws.shadow_value, ws.occluded, ws.cache_L, stats,
                            clock);
        stats.secondary_rays += ws.gather.size();
    }
    StageClock clock;
    const RadiusRule rule = cs.minimum_radius ? RadiusRule::Minimum : RadiusRule::Harmonic;
    for (const CacheRequest& q : ws.requests) {
        const IrradianceRecord rec =
            build_record(q.p, q.s, q.t, q.n, strata_, &ws.cache_L[q.first], &ws.cache_dist[q.first],
                         rule, q.r_min, q.r_min * cs.r_max_factor);
        radiance[q.slot] += q.weight * rec.e;
        ws.new_records.push_back(rec);
    }
    stats.cache_records += ws.requests.size();
    stats.stage_items[int(Stage::CacheRecords)] += ws.requests.size();
    stats.stage_seconds[int(Stage::CacheRecords)] += clock.lap();
}

void PhotonIntegrator::direct_light(const SurfacePoint& sp, const Material& m, const Vec3& wo,
                                    const warp::Frame& frame, const RGB& weight, uint32_t slot,
                                    const SampleJob& job, uint32_t depth, PhotonCameraWorkspace& ws,
                                    std::vector<RGB>& radiance) const {
    if (lights_.empty()) return;
    const BsdfContext ctx{sp.front_face, Transport::Radiance};
    float pick;
    const uint32_t li = lights_.select(rand(job, depth, kDimLight), pick);
    LightSample ls;
    if (!lights_.sample_li(li, sp.p,
                           {rand(job, depth, kDimLight + 1), rand(job, depth, kDimLight + 2)},
                           rand(job, depth, kDimLight + 3), ls) ||
        dot(ls.wi, sp.ng) <= 0.f)
        return;
    const Vec3 wi = frame.to_local(ls.wi);
    const RGB f = m.bsdf.f_restricted(wo, wi, ctx, kDiffuse | kGlossy);
    const RGB value = weight * f * ls.Li * (std::fabs(wi.z) / (pick * ls.pdf));
    if (value.is_black()) return;
    // Shadow photons: among the nearest photons of this light, only direct ones mean lit,
    // only shadow ones mean dark; a mix (a penumbra) needs the ray.
    int verdict = -1;
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
    }
    if (verdict >= 0) {
        ++ws.saved;
        if (verdict == 1) radiance[slot] += value;
        return;
    }
    const float tmax = std::isinf(ls.dist) ? kInfinity : ls.dist * (1.f - 1e-4f) - sp.epsilon;
    ws.shadow.push(offset_origin(sp, ls.wi), ls.wi, 0.f, tmax, slot);
    ws.shadow_value.push_back(value);
}

void PhotonIntegrator::gather_rays(const SurfacePoint& sp, const Material& m, const Vec3& wo,
                                   const warp::Frame& frame, const RGB& weight, uint32_t slot,
                                   const SampleJob& job, uint32_t depth,
                                   PhotonCameraWorkspace& ws) const {
    const PhotonSettings& ps = scene_.render.photon;
    const uint32_t n = ps.gather_rays;
    if (n == 0 || maps_.global.empty()) return;
    const BsdfContext ctx{sp.front_face, Transport::Radiance};
    const uint64_t key = rng::hash(job.id, depth, 0x6a7, 0);
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
        const Point2 u = sample_pattern(SamplerKind::Jittered, g, n, seed_, key);
        Vec3 wl;
        RGB f;
        float pdf;
        if (guided) {
            wl = ws.guide.sample(u, pdf);
            f = m.bsdf.f_restricted(wo, wl, ctx, kDiffuse | kGlossy);
        } else {
            BsdfSample bs;
            if (!m.bsdf.sample(wo, rng::uniform(seed_, key, g, 2), u, ctx, bs, kDiffuse | kGlossy))
                continue;
            // The restricted sample is over the non-delta lobes only; its weight is theirs.
            wl = bs.wi;
            f = bs.f;
            pdf = bs.pdf;
        }
        if (!(pdf > 0.f)) continue;
        const Vec3 wi = frame.to_world(wl);
        if (dot(wi, sp.ng) <= 0.f) continue;
        const RGB w = weight * f * (std::fabs(wl.z) / (pdf * float(n)));
        if (w.is_black()) continue;
        ws.gather.push(offset_origin(sp, wi), wi, 0.f, kInfinity, slot);
        ws.gather_weight.push_back(w);
    }
}

RGB PhotonIntegrator::photon_radiance(const SurfacePoint& sp, const Material& m,
                                      const Vec3& d) const {
    const warp::Frame frame(sp.ns);
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
                                    float* first_dist, RenderStats& stats) const {
    StageClock clock;
    std::size_t rays = 0;
    for (uint32_t depth = 0; !ws.gather.empty(); ++depth) {
        accel_.intersect(ws.gather, ws.hits, stats.trace);
        rays += ws.gather.size();
        ws.gather_next.clear();
        ws.gather_weight_next.clear();
        for (std::size_t i = 0; i < ws.gather.size(); ++i) {
            const uint32_t slot = ws.gather.id[i];
            const RGB& w = ws.gather_weight[i];
            const uint32_t geom = ws.hits.geom[i];
            if (depth == 0 && first_dist)
                first_dist[slot] = geom == kNoHit ? kInfinity : ws.hits.t[i];
            if (geom == kNoHit) {
                radiance[slot] += w * scene_.background;
                continue;
            }
            const Vec3 d = ws.gather.direction(i);
            const SurfacePoint sp = surface_at(scene_, ws.gather, ws.hits, i);
            const Material& m = scene_.materials[scene_.objects[geom].material];
            // Emission is not counted: direct light came from NEE, and light through
            // specular surfaces from the caustic map.
            if (m.bsdf.empty()) continue;
            // The non-delta lobes from the photons, the delta ones followed below: both
            // parts are taken whole, so neither is reweighted.
            if (m.bsdf.has_non_delta()) radiance[slot] += w * photon_radiance(sp, m, d);
            if (m.bsdf.has_delta() && depth < kGatherSpecularDepth) {
                const warp::Frame frame(sp.ns);
                const Vec3 wo = frame.to_local(-d);
                const BsdfContext ctx{sp.front_face, Transport::Radiance};
                // Follow the delta lobes deterministically (both branches of a dielectric).
                Vec3 dirs[Bsdf::kMaxLobes * 2];
                RGB dw[Bsdf::kMaxLobes * 2];
                const int k = m.bsdf.specular_directions(wo, ctx, dirs, dw, Bsdf::kMaxLobes * 2);
                for (int j = 0; j < k; ++j) {
                    const RGB wj = w * dw[j];
                    if (wj.max_component() < 1e-4f) continue;
                    const Vec3 wi = frame.to_world(dirs[j]);
                    ws.gather_next.push(offset_origin(sp, wi), wi, 0.f, kInfinity, slot);
                    ws.gather_weight_next.push_back(wj);
                }
            }
        }
        std::swap(ws.gather, ws.gather_next);
        std::swap(ws.gather_weight, ws.gather_weight_next);
    }
    stats.secondary_rays += rays;
    stats.stage_items[int(Stage::FinalGather)] += rays;
    stats.stage_seconds[int(Stage::FinalGather)] += clock.lap();
}

void PhotonIntegrator::trace(const std::vector<SampleJob>& jobs, IntegratorWorkspace& base,
                             std::vector<RGB>& radiance, RenderStats& stats) const {
    PhotonCameraWorkspace& ws = static_cast<PhotonCameraWorkspace&>(base);
    StageClock clock;
    const std::size_t n = jobs.size();
    radiance.assign(n, RGB{0.f});
    ws.beta.assign(n, RGB{1.f});
    ws.rays.clear();
    ws.shadow.clear();
    ws.shadow_value.clear();
    ws.gather.clear();
    ws.gather_weight.clear();
    ws.path_length.assign(n, 0.f);
    ws.requests.clear();
    ws.cache_rays.clear();
    ws.cache_L.clear();
    ws.cache_dist.clear();
    ws.new_records.clear();
    ws.lookup = {};
    ws.cache_trace = {};
    generate_camera_rays(scene_, jobs, seed_, ws.rays);
    stats.camera_rays += n;
    stats.stage_items[int(Stage::Generate)] += n;
    stats.stage_seconds[int(Stage::Generate)] += clock.lap();

    // Camera rays through specular chains to the visible points.
    for (uint32_t depth = 0; !ws.rays.empty(); ++depth) {
        accel_.intersect(ws.rays, ws.hits, stats.trace);
        stats.stage_items[int(Stage::Intersect)] += ws.rays.size();
        stats.stage_seconds[int(Stage::Intersect)] += clock.lap();
        ws.next.clear();
        for (std::size_t i = 0; i < ws.rays.size(); ++i) {
            const uint32_t slot = ws.rays.id[i];
            const SampleJob& job = jobs[slot];
            RGB& beta = ws.beta[slot];
            const uint32_t geom = ws.hits.geom[i];
            if (geom == kNoHit) {
                radiance[slot] += beta * scene_.background;
                continue;
            }
            const Vec3 d = ws.rays.direction(i);
            ws.path_length[slot] += ws.hits.t[i];
            const SurfacePoint sp = surface_at(scene_, ws.rays, ws.hits, i);
            const Material& m = scene_.materials[scene_.objects[geom].material];
            // Emitters seen from the camera or through specular chains (L S* E paths have no
            // diffuse vertex, so no photon estimate holds them).
            if (m.emits_towards(sp.front_face)) radiance[slot] += beta * m.emission;
            if (m.bsdf.empty()) continue;
            const float p_delta = m.bsdf.selection_probability(kSpecular);
            if (m.bsdf.has_delta() && rand(job, depth, kDimChoice) < p_delta) {
                if (depth >= scene_.render.max_depth) continue;
                const warp::Frame frame(sp.ns);
                const Vec3 wo = frame.to_local(-d);
                const BsdfContext ctx{sp.front_face, Transport::Radiance};
                BsdfSample bs;
                if (!m.bsdf.sample(wo, rand(job, depth, kDimLobe),
                                   {rand(job, depth, kDimLobe + 1), rand(job, depth, kDimLobe + 2)},
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
            shade_visible(sp, m, d, w, slot, job, depth, ws, radiance);
        }
        stats.stage_items[int(Stage::Shade)] += ws.rays.size();
        stats.stage_seconds[int(Stage::Shade)] += clock.lap();
        stats.secondary_rays += ws.next.size();
        std::swap(ws.rays, ws.next);
    }
    stats.shadow_rays_saved += ws.saved;
    ws.saved = 0;
    resolve_shadow_rays(accel_, ws.shadow, ws.shadow_value, ws.occluded, radiance, stats, clock);
    final_gather(ws, radiance, nullptr, stats);
    compute_records(ws, radiance, stats);
    stats.trace.merge(ws.cache_trace);
    stats.shadow_rays += ws.lookup.visibility_tests;
    stats.cache.merge(ws.lookup);
}

}  // namespace foton
