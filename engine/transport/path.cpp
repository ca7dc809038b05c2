#include "path.h"

#include <cmath>

#include "engine/core/warp.h"
#include "mis.h"
#include "shadow_batch.h"
#include "surface.h"

namespace foton {

namespace {
// Random dimensions per bounce: light choice, light position (3), BSDF lobe and direction (3),
// Russian roulette. The distributed tracer's shadow samples use their own keyed streams.
constexpr uint32_t kDimsPerBounce = 8;
constexpr uint32_t kDimLightSelect = 0, kDimLight = 1, kDimBsdf = 4, kDimRoulette = 7;
}  // namespace

PathIntegrator::PathIntegrator(const Scene& scene, const Intersector& accel, const LightSet& lights,
                               uint64_t seed, bool distributed)
    : scene_(scene), accel_(accel), lights_(lights), seed_(seed), distributed_(distributed) {}

float PathIntegrator::rand(const SampleJob& j, uint32_t depth, uint32_t k) const {
    return rng::uniform(seed_, kPathStream, j.id, uint64_t(depth) * kDimsPerBounce + k);
}

void PathIntegrator::shade(uint32_t depth, const std::vector<SampleJob>& jobs, PathWorkspace& ws,
                           std::vector<RGB>& radiance) const {
    const RenderSettings& rs = scene_.render;
    ws.next.clear();
    ws.shadow.clear();
    ws.shadow_value.clear();
    const bool nee = distributed_ || rs.nee;
    const MisHeuristic mis = distributed_ ? MisHeuristic::None : rs.mis;
    const RGB ambient = scene_.ambient.radiance();

    auto queue_shadow = [&](const SurfacePoint& sp, const LightSample& ls, const RGB& value,
                            uint32_t slot) {
        const Vec3 o = offset_origin(sp, ls.wi);
        const float tmax = std::isinf(ls.dist) ? kInfinity : ls.dist * (1.f - 1e-4f) - sp.epsilon;
        ws.shadow.push(o, ls.wi, 0.f, tmax, slot);
        ws.shadow_value.push_back(value);
    };

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
        const SurfacePoint sp = surface_at(scene_, ws.rays, ws.hits, i);
        const Material& m = scene_.materials[scene_.objects[geom].material];

        // Emission found by this ray, weighted against having sampled it as a light.
        if (m.emits_towards(sp.front_face)) {
            float w = 1.f;
            if (depth > 0 && !ws.specular_prev[slot] && nee && !distributed_) {
                if (mis == MisHeuristic::None) {
                    w = 0.f;
                } else {
                    const int li = lights_.emitter_of(geom);
                    const float pl =
                        li < 0 ? 0.f
                               : lights_.pmf(uint32_t(li)) *
                                     lights_.pdf_li(uint32_t(li), ws.p_prev[slot], sp.p, sp.ng);
                    w = mis_weight_bsdf(mis, ws.pdf_prev[slot], pl);
                }
            }
            radiance[slot] += beta * m.emission * w;
        }
        if (depth >= rs.max_depth || m.bsdf.empty()) continue;

        const warp::Frame frame(sp.ns);
        const Vec3 wo = frame.to_local(-d);
        const BsdfContext ctx{sp.front_face, Transport::Radiance};

        if (distributed_) {
            const RGB amb = m.type == MaterialType::Generic ? m.base_color * m.c_diffuse
                                                            : m.base_color * m.c_ambient;
            radiance[slot] += beta * amb * ambient;
        }

        // Next event estimation.
        if (nee && m.bsdf.has_non_delta() && !lights_.empty()) {
            auto estimate = [&](uint32_t li, float pick_pdf, Point2 u, float uc, float scale) {
                LightSample ls;
                if (!lights_.sample_li(li, sp.p, u, uc, ls)) return;
                if (dot(ls.wi, sp.ng) <= 0.f) return;
                const Vec3 wi = frame.to_local(ls.wi);
                const bool delta = lights_.emitter(li).is_delta();
                // The distributed tracer's glossy lobes see area lights by being sampled.
                const uint8_t only =
                    distributed_ && !delta ? uint8_t(kDiffuse) : uint8_t(kDiffuse | kGlossy);
                const RGB f = m.bsdf.f_restricted(wo, wi, ctx, only);
                if (f.is_black()) return;
                const float pl = pick_pdf * ls.pdf;
                const float w = delta ? 1.f : mis_weight(mis, pl, m.bsdf.pdf(wo, wi, ctx));
                const RGB value = beta * f * ls.Li * (std::fabs(wi.z) * w * scale / pl);
                if (!value.is_black()) queue_shadow(sp, ls, value, slot);
            };
            if (distributed_) {
                const uint32_t n = rs.light_samples;
                for (uint32_t li = 0; li < lights_.size(); ++li) {
                    const uint32_t k = lights_.emitter(li).is_delta() ? 1 : n;
                    for (uint32_t s = 0; s < k; ++s) {
                        const uint64_t key = rng::hash(job.id, depth, li, 0);
                        const Point2 u = sample_pattern(SamplerKind::Jittered, s, k, seed_, key);
                        const float uc = rng::uniform(seed_, key, s, 2);
                        estimate(li, 1.f, u, uc, 1.f / float(k));
                    }
                }
            } else {
                float pick;
                const uint32_t li = lights_.select(rand(job, depth, kDimLightSelect), pick);
                estimate(li, pick, {rand(job, depth, kDimLight), rand(job, depth, kDimLight + 1)},
                         rand(job, depth, kDimLight + 2), 1.f);
            }
        }

        // Continue the path by sampling the BSDF.
        BsdfSample bs;
        const uint8_t only = distributed_ ? uint8_t(kGlossy | kSpecular) : uint8_t(0xff);
        if (!m.bsdf.sample(wo, rand(job, depth, kDimBsdf),
                           {rand(job, depth, kDimBsdf + 1), rand(job, depth, kDimBsdf + 2)}, ctx,
                           bs, only))
            continue;
        const Vec3 wi = frame.to_world(bs.wi);
        // A direction on the wrong side of the true surface would leak light through it.
        const float side = dot(wi, sp.ng);
        if ((bs.flags & kTransmission) ? side >= 0.f : side <= 0.f) continue;
        beta *= bs.f * (std::fabs(bs.wi.z) / bs.pdf);
        if (beta.is_black()) continue;
        // Russian roulette: survive with the path's weight, capped at 1, and reweight.
        if (depth + 1 >= rs.rr_depth) {
            const float q = std::min(1.f, beta.max_component());
            if (rand(job, depth, kDimRoulette) >= q) continue;
            beta *= 1.f / q;
        }
        ws.pdf_prev[slot] = bs.pdf;
        ws.specular_prev[slot] = bs.is_delta();
        ws.p_prev[slot] = sp.p;
        ws.next.push(offset_origin(sp, wi), wi, 0.f, kInfinity, slot);
    }
}

void PathIntegrator::trace(const std::vector<SampleJob>& jobs, IntegratorWorkspace& base,
                           std::vector<RGB>& radiance, RenderStats& stats) const {
    PathWorkspace& ws = static_cast<PathWorkspace&>(base);
    StageClock clock;
    const std::size_t n = jobs.size();
    radiance.assign(n, RGB{0.f});
    ws.beta.assign(n, RGB{1.f});
    ws.pdf_prev.assign(n, 0.f);
    ws.specular_prev.assign(n, 1);
    ws.p_prev.assign(n, Vec3{});
    ws.rays.clear();
    generate_camera_rays(scene_, jobs, seed_, ws.rays);
    stats.camera_rays += n;
    stats.stage_items[int(Stage::Generate)] += n;
    stats.stage_seconds[int(Stage::Generate)] += clock.lap();

    for (uint32_t depth = 0; !ws.rays.empty(); ++depth) {
        accel_.intersect(ws.rays, ws.hits, stats.trace);
        stats.stage_items[int(Stage::Intersect)] += ws.rays.size();
        stats.stage_seconds[int(Stage::Intersect)] += clock.lap();

        shade(depth, jobs, ws, radiance);
        stats.stage_items[int(Stage::Shade)] += ws.rays.size();
        stats.stage_seconds[int(Stage::Shade)] += clock.lap();

        resolve_shadow_rays(accel_, ws.shadow, ws.shadow_value, ws.occluded, radiance, stats,
                            clock);
        stats.secondary_rays += ws.next.size();
        std::swap(ws.rays, ws.next);
    }
}

}  // namespace foton
