#include "light_tracer.h"

#include <cmath>

#include "engine/core/warp.h"
#include "engine/transport/common/camera_integrator.h"
#include "engine/transport/common/film_splats.h"
#include "engine/transport/common/surface.h"
#include "engine/transport/common/wavefront.h"

namespace foton {

namespace {
// The path's first random dimensions (the bounces' follow: light_tracer.h).
constexpr uint32_t kDimLightSelect = 0, kDimPos = 1, kDimDir = 3, kDimTriangle = 5;
}  // namespace

LightTracer::LightTracer(const RenderContext& ctx)
    : ctx_(ctx), kernels_([&] {
          KernelMaterials k = kernel_materials(ctx.scene);
          k.enabled = ctx.settings.simd_shading;
          return k;
      }()) {}

float LightTracer::rand(uint64_t path, uint32_t dim) const {
    return rng::uniform(ctx_.seed, kLightPathStream, path, dim);
}

bool splat_on_film(const Scene& scene, const Vec3& p, const Vec3& wc, float dist, const RGB& value,
                   FilmPoint& at, RGB& splat) {
    const Camera& cam = scene.camera;
    if (!cam.project(p, at.x, at.y, scene.film.filter.margin())) return false;
    splat = value * cam.importance(-dot(wc, cam.w), dist);
    return !splat.is_black();
}

bool continue_light_path(const Bsdf& bsdf, const warp::Frame& frame, const Vec3& wo,
                         const BsdfContext& ctx, const Vec3& ng, float adj, float u0, Point2 u12,
                         RGB& beta, Vec3& wi) {
    BsdfSample bs;
    if (!bsdf.sample(wo, u0, u12, ctx, bs)) return false;
    wi = frame.to_world(bs.wi);
    const float side = dot(wi, ng);
    if ((bs.flags & kTransmission) ? side >= 0.f : side <= 0.f) return false;
    beta *= bs.f * (adj * std::fabs(side) / bs.pdf);
    return !beta.is_black();
}

bool emitting_point_to_eye(const Emitter& em, const EmittedRay& er, const Vec3& wc, RGB& value,
                           Vec3& origin) {
    if (em.is_delta() || em.is_infinite()) return false;
    const EmissionSample& es = er.emission;
    const float c = dot(es.n, wc);
    const float cos_l = em.two_sided ? std::fabs(c) : c;
    if (!(cos_l > 0.f)) return false;
    value = es.Le * (cos_l / (er.pmf * es.pdf_pos));
    const float eps = offset_epsilon(es.p, 0.f);
    origin = es.p + es.n * (c > 0.f ? eps : -eps);
    return true;
}

bool LightTracer::to_film(const Vec3& p, const Vec3& wc, float dist, const RGB& value,
                          FilmPoint& at, RGB& splat) const {
    return splat_on_film(ctx_.scene, p, wc, dist, value, at, splat);
}

void LightTracer::push_connection(const Vec3& o, const Vec3& wc, float tmax, const RGB& splat,
                                  FilmPoint at, uint32_t slot, LightTracerWorkspace& ws) const {
    ws.shadow.push(o, wc, 0.f, tmax, slot);
    ws.shadow_value.push_back(splat);
    ws.shadow_at.push_back(at);
}

void LightTracer::shade_vertex(uint64_t first, uint32_t depth, std::size_t i,
                               LightTracerWorkspace& ws) const {
    const Camera& cam = ctx_.scene.camera;
    const RenderSettings& rs = ctx_.settings;
    const uint32_t vertex = depth + 1;  // scattering vertices so far, this one included
    const uint32_t geom = ws.hits.geom[i];
    const uint32_t slot = ws.rays.id[i];
    const uint64_t path = first + slot;
    const Vec3 d = ws.rays.direction(i);
    const SurfacePoint sp = surface_at(ctx_.scene, ws.rays, ws.hits, i);
    std::optional<Material> scratch;
    const Material& m = ctx_.scene.material_at(geom, sp.tex(), scratch);
    if (m.bsdf.empty() || vertex > rs.max_depth) return;
    RGB& beta = ws.beta[slot];
    const warp::Frame frame = sp.frame();
    const Vec3 wl = -d;  // towards the light
    const Vec3 wo = frame.to_local(wl);
    const BsdfContext ctx{sp.front_face, Transport::Importance};
    const float wl_ng = std::fabs(dot(wl, sp.ng));
    if (wl_ng == 0.f) return;
    // Veach's adjoint correction for shading normals: |wl.ns| |w.ng| / (|wl.ng| |w.ns|).
    const float adj = std::fabs(wo.z) / wl_ng;

    if (m.bsdf.has_non_delta()) {
        const Vec3 to = cam.eye - sp.p;
        const float dist = length(to);
        const Vec3 wc = to / dist;
        // The eye behind the surface sees it through a rough dielectric's transmission.
        if (m.bsdf.side_allowed(wc, sp.ng)) {
            const float c_ng = std::fabs(dot(wc, sp.ng));
            const RGB f = m.bsdf.f(wo, frame.to_local(wc), ctx);
            FilmPoint at;
            RGB splat;
            if (!f.is_black() && to_film(sp.p, wc, dist, beta * f * (adj * c_ng), at, splat)) {
                const Vec3 o = offset_origin(sp, wc);
                push_connection(o, wc, length(cam.eye - o) * (1.f - 1e-4f), splat, at, slot, ws);
            }
        }
    }
    if (vertex >= rs.max_depth) return;
    const uint32_t dim = kLightDimFirstBounce + depth * kLightDimsPerBounce;
    Vec3 wi;
    if (!continue_light_path(m.bsdf, frame, wo, ctx, sp.ng, adj, rand(path, dim),
                             {rand(path, dim + 1), rand(path, dim + 2)}, beta, wi))
        return;
    if (vertex >= rs.rr_depth) {
        const float q = std::min(1.f, beta.max_component());
        if (rand(path, dim + 3) >= q) return;
        beta *= 1.f / q;
    }
    ws.next.push(offset_origin(sp, wi), wi, 0.f, kInfinity, slot);
}

void LightTracer::trace(uint64_t first, uint32_t count, LightTracerWorkspace& ws,
                        std::vector<Splat>& splats, RenderStats& stats) const {
    const Camera& cam = ctx_.scene.camera;
    StageClock clock;
    ws.rays.clear();
    ws.shadow.clear();
    ws.shadow_value.clear();
    ws.shadow_at.clear();
    ws.beta.assign(count, RGB{0.f});

    for (uint32_t k = 0; k < count; ++k) {
        const uint64_t path = first + k;
        EmittedRay er;
        if (!ctx_.lights.sample_ray(
                rand(path, kDimLightSelect), {rand(path, kDimPos), rand(path, kDimPos + 1)},
                {rand(path, kDimDir), rand(path, kDimDir + 1)}, rand(path, kDimTriangle), er))
            continue;
        const Emitter& em = ctx_.lights.emitter(er.light);
        const EmissionSample& es = er.emission;
        {
            // The emitting point itself, seen by the camera.
            const Vec3 to = cam.eye - es.p;
            const float dist = length(to);
            const Vec3 wc = to / dist;
            RGB value, splat;
            Vec3 o;
            FilmPoint at;
            if (emitting_point_to_eye(em, er, wc, value, o) &&
                to_film(es.p, wc, dist, value, at, splat))
                push_connection(o, wc, length(cam.eye - o) * (1.f - 1e-4f), splat, at, k, ws);
        }
        ws.beta[k] = er.beta;
        ws.rays.push(er.origin, es.dir, 0.f, kInfinity, k);
    }
    stats.samples += count;
    stats.add(Stage::Generate, count, clock);

    run_wavefront(ctx_.accel, ws.rays, ws.next, ws.hits, 0, stats, clock, [&](uint32_t depth) {
        // The hits on the kernel's materials through shade_lanes, grouped by glossy kind; the
        // others one at a time.
        const bool kernels = kernels_.enabled && depth + 1 <= ctx_.settings.max_depth;
        for (std::vector<uint32_t>& g : ws.kernel_groups) g.clear();
        for (std::size_t i = 0; i < ws.rays.size(); ++i) {
            const uint32_t geom = ws.hits.geom[i];
            if (geom == kNoHit) continue;
            if (kernels && kernels_.object_kernel[geom] == KernelKind::Diffuse)
                ws.kernel_groups[kernels_.object_group[geom]].push_back(uint32_t(i));
            else
                shade_vertex(first, depth, i, ws);
        }
        ws.kernel_entries.clear();
        for (const std::vector<uint32_t>& g : ws.kernel_groups)
            ws.kernel_entries.insert(ws.kernel_entries.end(), g.begin(), g.end());
        if (!ws.kernel_entries.empty()) shade_lanes(first, depth, ws);
    });

    // The connections, tested at once. Splats keep the order the connections were made in,
    // which depends only on the chunk's paths.
    if (!ws.shadow.empty()) {
        ctx_.accel.occluded(ws.shadow, ws.occluded, stats.trace);
        stats.shadow_rays += ws.shadow.size();
        stats.add(Stage::Occlusion, ws.shadow.size(), clock);
        for (std::size_t i = 0; i < ws.shadow.size(); ++i)
            if (!ws.occluded[i])
                push_splats(ctx_.scene.film, ws.shadow_at[i], ws.shadow_value[i], splats);
    }
}

}  // namespace foton
