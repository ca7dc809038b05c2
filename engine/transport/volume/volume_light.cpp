#include "volume_light.h"

#include <cmath>

#include "engine/core/rng.h"
#include "engine/core/rng_streams.h"
#include "engine/core/warp.h"
#include "engine/transport/common/film_splats.h"
#include "engine/transport/common/medium_locate.h"
#include "engine/transport/common/medium_tracking.h"
#include "engine/transport/common/surface.h"
#include "engine/transport/light/light_tracer.h"

namespace foton {

namespace {
// The connections' keys for ratio tracking: the path and its vertex.
uint64_t connection_key(uint64_t path, uint32_t vertex) {
    return path * 1024 + std::min<uint32_t>(vertex, 1023);
}
}  // namespace

VolumeLightTracer::VolumeLightTracer(const RenderContext& ctx)
    : ctx_(ctx), light_medium_(light_media(ctx.scene, ctx.accel, ctx.lights)) {}

void VolumeLightTracer::connect(const Vec3& p, const Vec3& o, int32_t medium, const RGB& value,
                                uint64_t key, VolumeLightWorkspace& ws) const {
    const Camera& cam = ctx_.scene.camera;
    const Vec3 to = cam.eye - p;
    const float dist = length(to);
    if (!(dist > 0.f)) return;
    const Vec3 wc = to / dist;
    FilmPoint at;
    RGB splat;
    if (!splat_on_film(ctx_.scene, p, wc, dist, value, at, splat)) return;
    const uint32_t slot = uint32_t(ws.shadow_at.size());
    ws.shadow.push(o, wc, length(cam.eye - o) * (1.f - 1e-4f), medium, slot, splat, key);
    ws.shadow_at.push_back(at);
}

template <class Uniform>
void VolumeLightTracer::shade_surface(std::size_t r, uint64_t path, VolumeLightWorkspace& ws,
                                      Uniform&& u) const {
    const RenderSettings& rs = ctx_.settings;
    const Scene& scene = ctx_.scene;
    const uint32_t slot = ws.rays.id[r];
    const uint32_t geom = ws.hits.geom[r];
    const Vec3 d = ws.rays.direction(r);
    const SurfacePoint sp = surface_at(scene, ws.rays, ws.hits, r);
    std::optional<Material> scratch;
    const Material& m = scene.material_at(geom, sp.tex(), scratch);
    if (m.is_interface) {
        cross_interface(scene, geom, sp, d, slot, ws.medium[slot], ws.crossings[slot], ws.next);
        return;
    }
    const uint32_t vertex = ++ws.bounces[slot];
    if (m.bsdf.empty() || vertex > rs.max_depth) return;
    RGB& beta = ws.beta[slot];
    const warp::Frame frame = sp.frame();
    const Vec3 wo = frame.to_local(-d);
    const BsdfContext ctx{sp.front_face, Transport::Importance};
    const float wl_ng = std::fabs(dot(d, sp.ng));
    if (wl_ng == 0.f) return;
    // Veach's adjoint correction for shading normals, as the light tracer has it.
    const float adj = std::fabs(wo.z) / wl_ng;
    if (m.bsdf.has_non_delta()) {
        const Vec3 wc = normalize(scene.camera.eye - sp.p);
        if (m.bsdf.side_allowed(wc, sp.ng)) {
            const RGB f = m.bsdf.f(wo, frame.to_local(wc), ctx);
            if (!f.is_black())
                connect(
                    sp.p, offset_origin(sp, wc), medium_after(scene, geom, sp, wc, ws.medium[slot]),
                    beta * f * (adj * std::fabs(dot(wc, sp.ng))), connection_key(path, vertex), ws);
        }
    }
    if (vertex >= rs.max_depth) return;
    // The numbers drawn in a fixed order (function arguments are evaluated in any).
    const float u0 = u(), u1 = u(), u2 = u();
    Vec3 wi;
    if (!continue_light_path(m.bsdf, frame, wo, ctx, sp.ng, adj, u0, {u1, u2}, beta, wi)) return;
    if (vertex >= rs.rr_depth) {
        const float q = std::min(1.f, beta.max_component());
        if (u() >= q) return;
        beta *= 1.f / q;
    }
    ws.medium[slot] = medium_after(scene, geom, sp, wi, ws.medium[slot]);
    ws.next.push(offset_origin(sp, wi), wi, 0.f, kInfinity, slot);
}

void VolumeLightTracer::trace(uint64_t first, uint32_t count, VolumeLightWorkspace& ws,
                              std::vector<Splat>& splats, RenderStats& stats) const {
    const Scene& scene = ctx_.scene;
    const RenderSettings& rs = ctx_.settings;
    StageClock clock;
    const uint64_t prefix = rng::stream_prefix(ctx_.seed, kVolumeLightStream);
    ws.rays.clear();
    ws.shadow.clear();
    ws.shadow_at.clear();
    ws.beta.assign(count, RGB{0.f});
    ws.medium.assign(count, kNoMedium);
    ws.bounces.assign(count, 0);
    ws.crossings.assign(count, 0);
    ws.draws.assign(count, 6);  // numbers 0..5 place the emission
    auto u = [&](uint32_t slot) {
        return rng::uniform_from(prefix, first + slot, ws.draws[slot]++);
    };
    for (uint32_t k = 0; k < count; ++k) {
        const uint64_t path = first + k;
        auto dim = [&](uint32_t i) { return rng::uniform_from(prefix, path, i); };
        EmittedRay er;
        if (!ctx_.lights.sample_ray(dim(0), {dim(1), dim(2)}, {dim(3), dim(4)}, dim(5), er))
            continue;
        const Emitter& em = ctx_.lights.emitter(er.light);
        const EmissionSample& es = er.emission;
        ws.medium[k] = light_medium_[er.light];
        // The emitting point itself, seen by the camera through the media.
        RGB value;
        Vec3 o;
        if (emitting_point_to_eye(em, er, normalize(scene.camera.eye - es.p), value, o))
            connect(es.p, o, ws.medium[k], value, connection_key(path, 0), ws);
        ws.beta[k] = er.beta;
        ws.rays.push(er.origin, es.dir, 0.f, kInfinity, k);
    }
    stats.samples += count;
    stats.add(Stage::Generate, count, clock);
    while (!ws.rays.empty()) {
        ctx_.accel.intersect(ws.rays, ws.hits, stats.trace);
        stats.add(Stage::Intersect, ws.rays.size(), clock);
        ws.next.clear();
        ws.flights.track_batch(scene, ws.rays, ws.hits, ws.medium, ws.beta, rs.simd_shading,
                               ws.flight_of, u);
        for (std::size_t r = 0; r < ws.rays.size(); ++r) {
            const uint32_t slot = ws.rays.id[r];
            const uint64_t path = first + slot;
            const uint32_t geom = ws.hits.geom[r];
            const Vec3 d = ws.rays.direction(r);
            auto draw = [&] { return u(slot); };
            RGB& beta = ws.beta[slot];
            if (const int32_t mi = ws.medium[slot]; mi != kNoMedium) {
                const Medium& med = scene.media[std::size_t(mi)];
                const FreeFlight f = flight_of_entry(scene, ws.flights, ws.flight_of, ws.rays,
                                                     ws.hits, r, mi, beta, draw);
                if (f.event == FreeFlight::Event::Absorb) continue;
                beta *= f.weight;
                if (f.event == FreeFlight::Event::Scatter) {
                    const uint32_t vertex = ++ws.bounces[slot];
                    if (vertex > rs.max_depth || beta.is_black()) continue;
                    const Vec3 p = ws.rays.origin(r) + d * f.t;
                    const Vec3 wc = normalize(scene.camera.eye - p);
                    connect(p, p, mi, beta * henyey_greenstein(dot(-d, wc), med.g),
                            connection_key(path, vertex), ws);
                    if (vertex >= rs.max_depth) continue;
                    if (vertex >= rs.rr_depth) {
                        const float q = std::min(1.f, beta.max_component());
                        if (draw() >= q) continue;
                        beta *= 1.f / q;
                    }
                    // The phase function is its own sampling density: beta stays.
                    Vec3 wi;
                    sample_henyey_greenstein(-d, med.g, {draw(), draw()}, wi);
                    ws.next.push(p, wi, 0.f, kInfinity, slot);
                    continue;
                }
            }
            if (geom == kNoHit) continue;
            shade_surface(r, path, ws, draw);
        }
        stats.add(Stage::Shade, ws.rays.size(), clock);
        std::swap(ws.rays, ws.next);
    }
    // The connections, through the media on the way; splats in connection order.
    if (!ws.shadow.empty()) {
        ws.arrived.assign(ws.shadow_at.size(), RGB{0.f});
        ws.shadow.resolve(scene, ctx_.accel, TransmittanceEstimator::Exact, ctx_.seed, ws.arrived,
                          stats, clock);
        for (std::size_t i = 0; i < ws.arrived.size(); ++i)
            if (!ws.arrived[i].is_black())
                push_splats(scene.film, ws.shadow_at[i], ws.arrived[i], splats);
    }
}

}  // namespace foton
