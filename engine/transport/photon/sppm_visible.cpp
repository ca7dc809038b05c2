#include "sppm_visible.h"

#include <cmath>
#include <optional>

#include "engine/core/rng.h"
#include "engine/core/rng_streams.h"
#include "engine/transport/common/surface.h"

namespace foton {

float VisiblePoints::rand(uint64_t pass, uint64_t pixel, uint32_t dim) const {
    return rng::uniform(ctx_.seed + pass * 0x9e3779b97f4a7c15ull, kSppmStream, pixel, dim);
}

void VisiblePoints::trace_row(uint64_t pass, uint64_t light_pass, uint32_t y, SppmPixel* row,
                              VisibleRowWork& work, RenderStats& stats) const {
    const uint32_t w = uint32_t(ctx_.scene.film.width);
    work.rays.clear();
    work.shadow.clear();
    work.shadow_add.clear();
    work.beta.assign(w, RGB{1.f});
    for (uint32_t x = 0; x < w; ++x) {
        const uint64_t pixel = ctx_.scene.film.pixel_id(x, y);
        const Point2 j =
            ctx_.scene.film.filter.pixel_position({rand(pass, pixel, 0), rand(pass, pixel, 1)});
        Vec3 o, d;
        ctx_.scene.camera.generate(float(int(x) + ctx_.scene.film.x0) + j.x,
                                   float(int(y) + ctx_.scene.film.y0) + j.y,
                                   {rand(pass, pixel, 2), rand(pass, pixel, 3)}, o, d);
        row[x].valid = false;
        row[x].pass_direct = {};
        work.beta[x] *= ctx_.scene.film.filter.sample_weight(j);  // negative lobes: signed
        work.rays.push(o, d, 0.f, kInfinity, x);
    }
    stats.camera_rays += w;
    // Not flagged coherent: a row's neighbours make 16 x 1 packets, and on the dragon at 320^2
    // the packet kernel made this pass 5 % slower than the single-ray (here: stream) path.
    work.rays.coherent = false;
    for (uint32_t depth = 0; depth <= ctx_.settings.max_depth && !work.rays.empty(); ++depth) {
        ctx_.accel.intersect(work.rays, work.hits, stats.trace);
        work.next.clear();
        for (std::size_t r = 0; r < work.rays.size(); ++r)
            shade(pass, light_pass, y, depth, r, row, work, stats);
        std::swap(work.rays, work.next);
    }
    if (work.shadow.empty()) return;
    ctx_.accel.occluded(work.shadow, work.occluded, stats.trace);
    for (std::size_t i = 0; i < work.shadow.size(); ++i)
        if (!work.occluded[i]) row[work.shadow.id[i]].pass_direct += work.shadow_add[i];
}

void VisiblePoints::shade(uint64_t pass, uint64_t light_pass, uint32_t y, uint32_t depth,
                          std::size_t r, SppmPixel* row, VisibleRowWork& work,
                          RenderStats& stats) const {
    const uint32_t x = work.rays.id[r];
    const uint64_t pixel = ctx_.scene.film.pixel_id(x, y);
    SppmPixel& px = row[x];
    RGB& beta = work.beta[x];
    const Vec3 d = work.rays.direction(r);
    if (work.hits.geom[r] == kNoHit) {
        px.pass_direct += beta * ctx_.scene.background_along(work.rays.origin(r), d);
        return;
    }
    const SurfacePoint sp = surface_at(ctx_.scene, work.rays, work.hits, r);
    const uint32_t mi = ctx_.scene.objects[work.hits.geom[r]].material;
    std::optional<Material> scratch;
    const Material& m = ctx_.scene.material_at(work.hits.geom[r], sp.tex(), scratch);
    if (m.emits_towards(sp.front_face)) px.pass_direct += beta * m.emission;
    if (m.bsdf.empty()) return;
    const warp::Frame frame = sp.frame();
    const Vec3 wo = frame.to_local(-d);
    const BsdfContext ctx{sp.front_face, Transport::Radiance};
    const uint32_t dim = 8 + depth * 8;
    const float p_delta = m.bsdf.selection_probability(kSpecular);
    if (m.bsdf.has_delta() && rand(pass, pixel, dim) < p_delta) {
        BsdfSample bs;
        if (!m.bsdf.sample(wo, rand(pass, pixel, dim + 1),
                           {rand(pass, pixel, dim + 2), rand(pass, pixel, dim + 3)}, ctx, bs,
                           kSpecular))
            return;
        const Vec3 wi = frame.to_world(bs.wi);
        const float side = dot(wi, sp.ng);
        if ((bs.flags & kTransmission) ? side >= 0.f : side <= 0.f) return;
        beta *= bs.f * (std::fabs(bs.wi.z) / (bs.pdf * p_delta));
        work.next.push(offset_origin(sp, wi), wi, 0.f, kInfinity, x);
        ++stats.secondary_rays;
        return;
    }
    if (m.bsdf.has_delta()) beta *= 1.f / (1.f - p_delta);
    // The visible point.
    px.valid = true;
    px.p = sp.p;
    px.ng = sp.ng;
    px.frame = frame;
    px.wo = wo;
    px.front = sp.front_face;
    px.material = mi;
    px.tex = sp.tex();
    px.beta = beta;
    if (ctx_.lights.empty()) return;
    LightPick pick;
    if (!ctx_.lights.pick(rand(light_pass, pixel, 4), sp.p, sp.ng, pick)) return;
    LightSample ls;
    if (!ctx_.lights.sample_li(pick.light, sp.p,
                               {rand(light_pass, pixel, 5), rand(light_pass, pixel, 6)},
                               rand(light_pass, pixel, 7), ls, pick.tri) ||
        !m.bsdf.side_allowed(ls.wi, sp.ng))
        return;
    const Vec3 wi = frame.to_local(ls.wi);
    const RGB f = m.bsdf.f(wo, wi, ctx);
    if (f.is_black()) return;
    const ShadowRay s = shadow_ray_to(sp, ls);
    ++stats.shadow_rays;
    work.shadow.push(s.origin, s.dir, 0.f, s.tmax, x);
    work.shadow_add.push_back(beta * f * ls.Li * (std::fabs(wi.z) / (pick.pmf * ls.pdf)));
}

}  // namespace foton
