#include "camera_medium_vertex.h"

#include <cmath>

#include "engine/core/rng.h"
#include "engine/scene/medium.h"
#include "light_end.h"

namespace foton {

namespace {

// The vertex as its joins see it.
struct CameraMediumVertex {
    uint32_t slot = 0, path = 0;  // the batch slot, the pixel's light path
    uint32_t len = 0;             // segments from the camera
    Vec3 p, wo;                   // where, and towards the previous vertex
    int32_t medium = kNoMedium;
    RGB beta;
    SubpathMis m;
    uint64_t key = 0;
};

void join_medium_vertex(const VcmContext& c, const LightPathStore& store,
                        const CameraMediumVertex& v, float u_select, Point2 u_light, float u_tri,
                        JoinRays& joins) {
    const VcmWeights& W = c.weights;
    if (!W.connect) return;
    const float g = c.scene.media[std::size_t(v.medium)].g;
    const int t = int(v.len) + 1;  // camera vertices of a strategy ending here
    SurfacePoint at{};             // a point in a medium has no surface to be pushed off
    at.p = v.p;
    auto layer = [&](int s) { return c.layers.enabled() ? c.layers.of(s, t) : 0u; };

    // s = 1: a light sample (the weights as at a surface vertex: camera_subpaths.cpp).
    if (!c.lights.empty()) {
        float pick;
        const uint32_t li = c.lights.select(u_select, pick);
        LightSample ls;
        if (c.lights.sample_li(li, v.p, u_light, u_tri, ls)) {
            const float phase = henyey_greenstein(dot(v.wo, ls.wi), g);
            const Emitter& em = c.lights.emitter(li);
            const float direct = pick * ls.pdf;
            const float direct_w = em.is_delta_position() ? direct * ls.dist * ls.dist : direct;
            float pdf_pos, pdf_dir;
            c.lights.pdf_le(li, ls.n_light, -ls.wi, pdf_pos, pdf_dir);
            const float emit = pick * pdf_pos * pdf_dir;
            const float cos_light =
                em.is_delta() || em.is_infinite() ? 1.f : std::fabs(dot(ls.n_light, ls.wi));
            const float w_light = em.is_delta() ? 0.f : W.mis(phase / direct);
            const float w_camera =
                W.mis(emit / (direct_w * cos_light)) * (v.m.dvcm + v.m.dvc * W.mis(phase));
            const float w = W.strategy(1, t, 1.f / (w_light + 1.f + w_camera));
            const RGB value = v.beta * ls.Li * (phase * w / direct);
            if (!value.is_black())
                joins.push(true, shadow_ray_to(at, ls), v.medium, v.slot, value, layer(1),
                           rng::hash(v.key, 0x22, v.len, 1));
        }
    }
    // s >= 2: the connections to the pixel's light path.
    const LightVertices& lv = store.vertices;
    const uint32_t first = store.first[v.path];
    for (uint32_t j = first; j < store.first[v.path + 1]; ++j) {
        if (lv.length[j] + v.len + 1 > c.max_segments) break;
        const Vec3 q = lv.position(j);
        const Vec3 to = q - v.p;
        const float dist2 = length_squared(to);
        if (!(dist2 > 0.f)) continue;
        const float dist = std::sqrt(dist2);
        const Vec3 dir = to / dist;
        LobeEval le;
        float ql, cos_l;
        if (!light_end(c.scene, lv, j, dir, le, ql, cos_l)) continue;
        const float phase = henyey_greenstein(dot(v.wo, dir), g);
        const RGB value = connection_value(W, v.m, v.beta, t, lv, j, {RGB{phase}, phase, phase},
                                           1.f, le, ql, dist2, 1.f, cos_l, 1.f, true);
        if (!value.is_black())
            joins.push(true, shadow_ray_to(at, q, lv.ng[j], offset_epsilon(q, dist)), v.medium,
                       v.slot, value, layer(int(lv.length[j]) + 1),
                       rng::hash(v.key, 0x22, v.len, 2 + (j - first)));
    }
}

}  // namespace

void scatter_in_medium(const VcmContext& c, const LightPathStore& store, CameraSubpathWorkspace& ws,
                       uint32_t slot, const Vec3& p, const Vec3& d, uint64_t key,
                       const MediumVertexNumbers& u) {
    SubpathMedia& media = ws.media;
    const uint32_t len = ws.length[slot] + 1;
    ws.length[slot] = len;
    SubpathMis& m = ws.mis[slot];
    m.arrive(length_squared(p - media.from[slot]), 1.f, c.weights);
    if (len >= c.max_segments) return;
    const int32_t mi = media.medium[slot];
    join_medium_vertex(c, store, {slot, ws.path[slot], len, p, -d, mi, ws.beta[slot], m, key},
                       u.select, u.light, u.triangle, ws.joins);
    // The phase function is its own sampling density: beta stays.
    Vec3 wi;
    const float pdf =
        sample_henyey_greenstein(-d, c.scene.media[std::size_t(mi)].g, u.direction, wi);
    m.scatter_medium(pdf, pdf, c.weights);
    ws.specular[slot] = 0;
    ws.p_prev[slot] = p;
    media.from[slot] = p;
    ws.next.push(p, wi, 0.f, kInfinity, slot);
}

}  // namespace foton
