#include "whitted.h"

#include <cmath>

#include "engine/core/optics.h"
#include "engine/core/rng.h"
#include "engine/core/sampler.h"
#include "engine/core/warp.h"
#include "engine/transport/common/shadow_batch.h"
#include "engine/transport/common/wavefront.h"
#include "engine/transport/run/camera_driver.h"

namespace foton {

namespace {

// The environment's and emissive objects' shadow samples take keys of their own beside the
// area lights' indices.
constexpr uint64_t kEnvironmentKey = 0xe4f1u << 16;
constexpr uint64_t kEmitterKey = 0xe417u << 16;

// Phong's empirical lobe plus the Lambertian term; f times cos is the reflected fraction.
RGB brdf(const Material& m, const Vec3& ns, const Vec3& wo, const Vec3& wi) {
    RGB f = m.base_color * (m.c_diffuse * kInvPi);
    if (m.type == MaterialType::Phong || m.type == MaterialType::Reflective) {
        const Vec3 r = reflect(-wi, ns);  // mirror direction of the light
        const float rdotwo = dot(r, wo);
        if (rdotwo > 0.f) f += m.specular_color * (m.c_specular * std::pow(rdotwo, m.exponent));
    }
    return f;
}

}  // namespace

WhittedIntegrator::WhittedIntegrator(const Scene& scene, const RenderSettings& settings,
                                     const Intersector& accel, uint64_t seed)
    : scene_(scene), settings_(settings), accel_(accel), seed_(seed), lights_(scene) {
    for (uint32_t i = 0; i < lights_.size(); ++i) {
        const EmitterType t = lights_.emitter(i).type;
        if (t == EmitterType::Sphere || t == EmitterType::Mesh) emissive_.push_back(i);
    }
    sampled_lights_ = !scene.lights.areas.empty() || !emissive_.empty() || scene.environment;
}

void WhittedIntegrator::generate(const std::vector<SampleJob>& jobs, WhittedWorkspace& ws) const {
    const std::size_t n = jobs.size();
    ws.rays.clear();
    ws.weight.assign(n, RGB{1.f});
    generate_camera_rays(scene_, settings_.sampler, jobs, seed_, ws.rays);
}

template <class Brdf>
void WhittedIntegrator::direct_light(const SurfacePoint& sp, const Brdf& brdf, const RGB& weight,
                                     uint32_t slot, uint64_t sample_index, uint32_t depth,
                                     WhittedWorkspace& ws, bool behind) const {
    const Lights& L = scene_.lights;
    // Queues shadow ray r towards direction wi (unit), carrying the contribution it makes if
    // nothing blocks it.
    auto add_ray = [&](const ShadowRay& r, const Vec3& wi, const RGB& incident) {
        float cos_s = dot(sp.ns, wi);
        const float cos_g = dot(sp.ng, wi);
        if (behind && cos_s < 0.f && cos_g < 0.f) {
            cos_s = -cos_s;
        } else if (cos_s <= 0.f || cos_g <= 0.f) {
            return;
        }
        const RGB value = weight * brdf(wi) * incident * cos_s;
        if (value.is_black()) return;
        ws.shadow.push(r.origin, r.dir, 0.f, r.tmax, slot);
        ws.shadow_value.push_back(value);
    };
    // The same towards a light at distance `dist` that is a point, a direction or a point on
    // a rectangle: stopping short of it is enough (a plane meets the ray only at its end).
    auto add = [&](const Vec3& wi, float dist, const RGB& incident) {
        const float tmax = std::isinf(dist) ? kInfinity : dist * (1.f - 1e-4f) - sp.epsilon;
        add_ray({offset_origin(sp, wi), wi, tmax}, wi, incident);
    };
    for (const PointLight& pl : L.points) {
        const Vec3 to = pl.position - sp.p;
        const float d2 = length_squared(to), d = std::sqrt(d2);
        add(to / d, d, pl.intensity * (1.f / (1.f + pl.attenuation * d2)));
    }
    for (const DirectionalLight& dl : L.directionals) add(-dl.direction, kInfinity, dl.radiance);
    for (const SpotLight& sl : L.spots) {
        const Vec3 to = sl.position - sp.p;
        const float d2 = length_squared(to), d = std::sqrt(d2);
        const Vec3 wi = to / d;
        const float f = sl.falloff(dot(-wi, sl.direction));
        if (f > 0.f) add(wi, d, sl.intensity * (f / (1.f + sl.attenuation * d2)));
    }
    for (uint32_t li = 0; li < L.areas.size(); ++li) {
        const AreaLight& al = L.areas[li];
        const uint64_t key = rng::hash(kLightStream, sample_index, depth, li);
        const float inv_n = 1.f / float(al.samples);
        for (uint32_t k = 0; k < al.samples; ++k) {
            const Point2 uv = sample_pattern(al.sampler, k, al.samples, seed_, key);
            const Vec3 q = al.corner + al.edge1 * uv.x + al.edge2 * uv.y;
            const Vec3 to = q - sp.p;
            const float d2 = length_squared(to), d = std::sqrt(d2);
            const Vec3 wi = to / d;
            const float cos_l = -dot(al.normal, wi);
            if (cos_l <= 0.f) continue;  // one-sided emitter seen from behind
            // Radiance to irradiance: L cos_l dA / d^2, the area density being n / A.
            add(wi, d, al.radiance * (cos_l * al.area * inv_n / d2));
        }
    }
    // Emissive objects and the environment, like area lights, by light_samples shadow rays,
    // drawn from next event estimation's densities (jittered over the unit square).
    for (uint32_t e : emissive_) {
        const uint32_t n = settings_.light_samples;
        const uint64_t key = rng::hash(kLightStream, sample_index, depth, kEmitterKey + e);
        for (uint32_t k = 0; k < n; ++k) {
            LightSample ls;
            if (lights_.sample_li(e, sp.p, sample_pattern(SamplerKind::Jittered, k, n, seed_, key),
                                  rng::uniform(seed_, key, k, 2), ls) &&
                ls.pdf > 0.f)
                add_ray(shadow_ray_to(sp, ls), ls.wi, ls.Li * (1.f / (float(n) * ls.pdf)));
        }
    }
    if (scene_.environment) {
        const Environment& env = *scene_.environment;
        const uint32_t n = settings_.light_samples;
        const uint64_t key = rng::hash(kLightStream, sample_index, depth, kEnvironmentKey);
        for (uint32_t k = 0; k < n; ++k) {
            float pdf;
            const Vec3 wi =
                env.sample(sp.p, sample_pattern(SamplerKind::Jittered, k, n, seed_, key), pdf);
            if (pdf > 0.f) add(wi, kInfinity, env.Le(sp.p, wi) * (1.f / (float(n) * pdf)));
        }
    }
}

void WhittedIntegrator::shade_generic(const ShadingPoint& v, WhittedWorkspace& ws,
                                      std::vector<RGB>& radiance) const {
    const SurfacePoint& sp = v.sp;
    const Material& m = v.m;
    const warp::Frame& frame = v.frame;
    const Vec3& wo = v.wo;
    const RGB& weight = v.weight;
    const uint32_t slot = v.slot, depth = v.depth;
    const uint64_t sample_index = v.key;
    const BsdfContext ctx{sp.front_face, Transport::Radiance};
    // Ambient light reflected by the diffuse lobes, as the thesis' c_ambient term.
    radiance[slot] += weight * m.base_color * scene_.ambient.radiance() * m.c_diffuse;
    if (m.bsdf.has_non_delta()) {
        direct_light(
            sp, [&](const Vec3& wi) { return m.bsdf.f(wo, frame.to_local(wi), ctx); }, weight, slot,
            sample_index, depth, ws, m.bsdf.transmits_non_delta());
    }
    if (depth >= settings_.max_depth) return;
    Vec3 dirs[Bsdf::kMaxLobes * 2];
    RGB w[Bsdf::kMaxLobes * 2];
    const int n = m.bsdf.specular_directions(wo, ctx, dirs, w, Bsdf::kMaxLobes * 2);
    for (int k = 0; k < n; ++k) {
        const RGB wk = weight * w[k];
        if (wk.max_component() < settings_.min_contribution) continue;
        const Vec3 wi = frame.to_world(dirs[k]);
        ws.next.push(offset_origin(sp, wi), wi, 0.f, kInfinity, slot);
        ws.next_weight.push_back(wk);
    }
}

void WhittedIntegrator::shade(uint32_t depth, const std::vector<SampleJob>& jobs,
                              WhittedWorkspace& ws, std::vector<RGB>& radiance) const {
    ws.shadow.clear();
    ws.shadow_value.clear();
    ws.next.clear();
    ws.next_weight.clear();
    const RGB ambient = scene_.ambient.radiance();
    const bool may_continue = depth < settings_.max_depth;
    // The sample index only keys the sampling of area lights, emitters and the environment.
    const bool has_sampled_lights = sampled_lights_;
    const float cutoff = settings_.min_contribution;
    auto spawn = [&](const SurfacePoint& sp, const Vec3& w, const RGB& weight, uint32_t slot) {
        if (!may_continue || weight.max_component() < cutoff) return;
        ws.next.push(offset_origin(sp, w), w, 0.f, kInfinity, slot);
        ws.next_weight.push_back(weight);
    };
    for (std::size_t i = 0; i < ws.rays.size(); ++i) {
        const uint32_t slot = ws.rays.id[i];
        const RGB& weight = ws.weight[i];
        const uint32_t geom = ws.hits.geom[i];
        if (geom == kNoHit) {
            radiance[slot] +=
                weight * scene_.background_along(ws.rays.origin(i), ws.rays.direction(i));
            continue;
        }
        const Vec3 d = ws.rays.direction(i);
        const SurfacePoint sp = surface_at(scene_, ws.rays, ws.hits, i);
        std::optional<Material> scratch;
        const Material& m = scene_.material_at(geom, sp.tex(), scratch);
        const Vec3 wo = -d;
        if (m.emits_towards(sp.front_face)) radiance[slot] += weight * m.emission;
        switch (m.type) {
            case MaterialType::Emitter:
                break;
            case MaterialType::Generic:
                shade_generic(ShadingPoint(sp, m, d, weight, slot, depth,
                                           has_sampled_lights ? jobs[slot].id : 0),
                              ws, radiance);
                break;
            case MaterialType::Matte:
            case MaterialType::Phong:
            case MaterialType::Reflective: {
                radiance[slot] += weight * m.base_color * ambient * m.c_ambient;
                const uint64_t sample = has_sampled_lights ? jobs[slot].id : 0;
                direct_light(
                    sp, [&](const Vec3& wi) { return brdf(m, sp.ns, wo, wi); }, weight, slot,
                    sample, depth, ws);
                if (m.type == MaterialType::Reflective) {
                    Vec3 r = reflect(d, sp.ns);
                    if (dot(r, sp.ng) <= 0.f) r = reflect(d, sp.ng);
                    spawn(sp, r, weight * m.reflective_color * m.c_reflective, slot);
                }
                break;
            }
            case MaterialType::Glass: {
                // Entering when the ray meets the geometry's outside.
                const float eta_i = sp.front_face ? 1.f : m.ior;
                const float eta_t = sp.front_face ? m.ior : 1.f;
                const float cos_i = std::clamp(dot(wo, sp.ns), 0.f, 1.f);
                const float F = fresnel_dielectric(cos_i, eta_i, eta_t);
                Vec3 r = reflect(d, sp.ns);
                if (dot(r, sp.ng) <= 0.f) r = reflect(d, sp.ng);
                spawn(sp, r, weight * F, slot);
                Vec3 t;
                if (F < 1.f && refract(d, sp.ns, eta_i / eta_t, t) && dot(t, sp.ng) < 0.f) {
                    // Radiance is scaled by (eta_i / eta_t)^2 across the interface.
                    const float scale = (1.f - F) * (eta_i * eta_i) / (eta_t * eta_t);
                    spawn(sp, t, weight * m.refraction_color * scale, slot);
                }
                break;
            }
        }
    }
}

void WhittedIntegrator::trace_phase(uint32_t /*phase*/, const std::vector<SampleJob>& jobs,
                                    IntegratorWorkspace& base, std::vector<RGB>& radiance,
                                    RenderStats& stats) const {
    WhittedWorkspace& ws = static_cast<WhittedWorkspace&>(base);
    StageClock clock;
    generate(jobs, ws);
    radiance.assign(jobs.size(), RGB{0.f});
    stats.camera_rays += ws.rays.size();
    stats.add(Stage::Generate, ws.rays.size(), clock);

    run_wavefront(
        accel_, ws.rays, ws.next, ws.hits, 0, std::numeric_limits<uint32_t>::max(), stats, clock,
        [&](uint32_t depth) { shade(depth, jobs, ws, radiance); },
        [&](uint32_t) {
            resolve_shadow_rays(accel_, ws.shadow, ws.shadow_value, ws.occluded, radiance, stats,
                                clock);
            std::swap(ws.weight, ws.next_weight);
        });
}

RenderResult render_whitted(const Scene& scene, const RenderSettings& settings,
                            const Intersector& accel, const RenderOptions& opt) {
    const WhittedIntegrator integrator(scene, settings, accel, opt.seed);
    return render_camera(scene, settings, integrator, opt);
}

}  // namespace foton
