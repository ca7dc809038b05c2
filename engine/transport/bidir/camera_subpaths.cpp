#include "camera_subpaths.h"

#include <cmath>
#include <limits>

#include "camera_medium_vertex.h"
#include "camera_starts.h"
#include "engine/core/rng.h"
#include "engine/core/warp.h"
#include "engine/transport/common/camera_integrator.h"
#include "engine/transport/common/medium_shadow.h"
#include "engine/transport/common/surface.h"
#include "engine/transport/common/wavefront.h"
#include "light_end.h"
#include "vcm_joins.h"

namespace foton {

namespace {
// Random dimensions per bounce: light choice, light position (2), mesh triangle, BSDF lobe
// and direction (2), Russian roulette; the pixel position comes from the renderer's sampler.
constexpr uint32_t kDimsPerBounce = 8, kDimSelect = 0, kDimLight = 1, kDimTriangle = 3,
                   kDimBsdf = 4, kDimRoulette = 7;

}  // namespace

void trace_camera_subpaths(const VcmContext& c, const LightPathStore& store, uint32_t first,
                           uint32_t count, CameraSubpathWorkspace& ws, std::vector<RGB>& radiance,
                           std::vector<RGB>* layers, RenderStats& stats) {
    const Scene& scene = c.scene;
    const Camera& cam = scene.camera;
    const VcmWeights& W = c.weights;
    const LightVertices& lv = store.vertices;
    const float n_paths = float(c.light_paths);
    StageClock clock;
    // What a strategy adds goes to the sample's radiance and, with strategy_images, to its
    // layer (strategy_layers.h).
    const uint32_t n_layers = c.layers.count();
    const bool split = layers && n_layers > 0;
    if (split) layers->assign(std::size_t(count) * n_layers, RGB{0.f});
    auto add = [&](uint32_t slot, uint32_t layer, const RGB& value) {
        radiance[slot] += value;
        if (split) (*layers)[std::size_t(slot) * n_layers + layer] += value;
    };
    auto rand = [&](uint32_t slot, uint32_t depth, uint32_t k) {
        if (c.primary)
            return c.primary[ws.path[slot]]->get(primary_camera_dim(depth * kDimsPerBounce + k));
        return rng::uniform(c.seed, kBidirCameraStream, c.iteration * c.light_paths + ws.path[slot],
                            uint64_t(depth) * kDimsPerBounce + k);
    };

    // The vertices whose joins go through the lobe-pair kernel: untextured materials the
    // diffuse kernel takes.
    const KernelMaterials* kernels = c.kernels && c.kernels->enabled ? c.kernels : nullptr;
    auto kernel_vertex = [&](uint32_t geom) {
        return kernels && kernels->object_kernel[geom] == KernelKind::Diffuse;
    };
    auto material_of = [&](uint32_t geom) { return scene.objects[geom].material; };
    SubpathMedia& media = ws.media;
    auto path_key = [&](uint32_t slot) { return c.iteration * c.light_paths + ws.path[slot]; };
    // A join from surface vertex sp (object geom) of path `slot`: through the medium on the
    // side it leaves to; `index` tells the path's joins apart for ratio tracking.
    auto push_shadow = [&](const ShadowRay& r, uint32_t geom, const SurfacePoint& sp, uint32_t slot,
                           const RGB& value, int s, int t, uint32_t index) {
        const int32_t medium =
            media.on ? medium_after(scene, geom, sp, r.dir, media.medium[slot]) : kNoMedium;
        ws.joins.push(media.on, r, medium, slot, value, split ? c.layers.of(s, t) : 0u,
                      media.on ? rng::hash(path_key(slot), 0x22, uint64_t(t - 1), index) : 0);
    };
    auto push_connection = [&](const SurfacePoint& sp, uint32_t geom, uint32_t j, float dist,
                               const RGB& value, uint32_t slot, int t) {
        const Vec3 q = lv.position(j);
        push_shadow(shadow_ray_to(sp, q, lv.ng[j], offset_epsilon(q, dist)), geom, sp, slot, value,
                    int(lv.length[j]) + 1, t, 2 + (j - store.first[ws.path[slot]]));
    };
    // The bounce's queued joins: every lobe pair through the kernel, then the connections'
    // shadow rays and the merges' sums, in the order they were queued.
    auto join_batched = [&] {
        if (ws.pairs.size() == 0) return;
        ws.pairs.evaluate(*kernels);
        auto eval = [&](uint32_t k) {
            return LobeEval{ws.pairs.f[k], ws.pairs.pdf[k], ws.pairs.pdf_rev[k]};
        };
        for (const QueuedConnection& qc : ws.connections) {
            const QueuedVertex& v = ws.vertices[qc.vertex];
            const float ql = scene.materials[material_of(lv.geom[qc.j])].bsdf.continuation();
            const RGB value = connection_value(W, v.m, v.beta, v.t, lv, qc.j, eval(qc.pair), v.q,
                                               eval(qc.pair + 1), ql, qc.dist2, qc.cos_c, qc.cos_l,
                                               qc.cos_shading);
            if (!value.is_black())
                push_connection(v.sp, v.geom, qc.j, std::sqrt(qc.dist2), value, v.slot, v.t);
        }
        RGB sum{0.f};
        for (std::size_t k = 0; k < ws.merges.size(); ++k) {
            const QueuedMerge& qm = ws.merges[k];
            const QueuedVertex& v = ws.vertices[qm.vertex];
            const LobeEval e = eval(qm.pair);
            if (!e.f.is_black()) sum += merge_term(W, v.m, lv, qm.j, e, v.q);
            if (k + 1 == ws.merges.size() || ws.merges[k + 1].vertex != qm.vertex) {
                add(v.slot, c.layers.merges(), v.beta * sum * W.vm_norm);
                sum = RGB{0.f};
            }
        }
    };

    radiance.assign(count, RGB{0.f});
    ws.path.resize(count);
    ws.beta.assign(count, RGB{1.f});
    ws.mis.assign(count, {});
    ws.p_prev.assign(count, Vec3{});
    ws.specular.assign(count, 1);
    ws.length.assign(count, 0);
    media.reset(c.media, c.seed, kBidirCameraMediumStream, count);
    ws.rays.clear();
    {
        start_camera_rays(c, first, count, ws);
        for (uint32_t k = 0; k < count; ++k) {
            const float cos_cam = dot(ws.rays.direction(k), cam.w);
            // Per pixel sample, the pinhole's solid-angle density is its importance at unit
            // distance; the light paths (N of them) would have found the point N times.
            ws.mis[k].dvcm = W.mis(n_paths / cam.importance(cos_cam, 1.f));
            ws.p_prev[k] = ws.rays.origin(k);
            if (media.on) {
                media.medium[k] = scene.camera_medium;
                media.key[k] = path_key(k);
                media.from[k] = ws.rays.origin(k);
            }
        }
    }
    stats.camera_rays += count;
    stats.add(Stage::Generate, count, clock);
    const RGB background = scene.background;

    // Interfaces cost a bounce of the wavefront and no vertex: with media the paths' lengths
    // end them.
    run_wavefront(
        c.accel, ws.rays, ws.next, ws.hits, 0,
        media.on ? std::numeric_limits<uint32_t>::max() : c.max_segments, stats, clock,
        [&](uint32_t depth) {
            ws.joins.clear();
            if (media.on) media.track(scene, ws.rays, ws.hits, ws.beta, c.settings.simd_shading);
            ws.pairs.clear();
            ws.vertices.clear();
            ws.connections.clear();
            ws.merges.clear();
            for (std::size_t i = 0; i < ws.rays.size(); ++i) {
                const uint32_t slot = ws.rays.id[i];
                const uint32_t geom = ws.hits.geom[i];
                const Vec3 d = ws.rays.direction(i);
                RGB& beta = ws.beta[slot];
                SubpathMis& m = ws.mis[slot];
                const uint32_t len = ws.length[slot] + 1;  // segments from the camera to here
                const int t = int(len) + 1;  // camera vertices of a strategy ending here
                float t_scatter = 0.f;
                const SubpathMedia::FlightEnd end =
                    media.fly(scene, ws.rays, ws.hits, i, beta, t_scatter);
                if (end == SubpathMedia::FlightEnd::Gone) continue;
                if (end == SubpathMedia::FlightEnd::Scattered) {
                    scatter_in_medium(
                        c, store, ws, slot, ws.rays.origin(i) + d * t_scatter, d, path_key(slot),
                        {rand(slot, depth, kDimSelect),
                         {rand(slot, depth, kDimLight), rand(slot, depth, kDimLight + 1)},
                         rand(slot, depth, kDimTriangle),
                         {rand(slot, depth, kDimBsdf + 1), rand(slot, depth, kDimBsdf + 2)}});
                    continue;
                }
                if (geom == kNoHit) {
                    if (!scene.environment) {
                        add(slot, c.layers.of(0, t), beta * background * W.strategy(0, t, 1.f));
                        continue;
                    }
                    float w = 1.f;
                    if (!W.connect) {
                        if (!ws.specular[slot]) continue;
                    } else if (len > 1) {
                        const uint32_t li = uint32_t(c.lights.environment());
                        float pdf_pos, pdf_dir;
                        c.lights.pdf_le(li, {}, -d, pdf_pos, pdf_dir);
                        const float emit = c.lights.pmf(li) * pdf_pos * pdf_dir;
                        w = 1.f / (1.f + W.mis(c.lights.environment_pdf(d)) * m.dvcm +
                                   W.mis(emit) * m.dvc);
                    }
                    add(slot, c.layers.of(0, t),
                        beta * scene.environment->Le(ws.rays.origin(i), d) * W.strategy(0, t, w));
                    continue;
                }
                const SurfacePoint sp = surface_at(scene, ws.rays, ws.hits, i);
                std::optional<Material> scratch;
                const Material& mat = scene.material_at(geom, sp.tex(), scratch);
                if (media.on && mat.is_interface) {
                    cross_interface(scene, geom, sp, d, slot, media.medium[slot],
                                    media.crossings[slot], ws.next);
                    continue;
                }
                const float cos_in = std::fabs(dot(d, sp.ng));
                if (cos_in == 0.f) continue;
                ws.length[slot] = len;
                const float t_hit = ws.hits.t[i];
                // The segment from the last vertex (across interfaces).
                const float d2 = media.on ? length_squared(sp.p - media.from[slot]) : t_hit * t_hit;
                m.arrive(d2, cos_in, W);

                // s = 0: the light this ray found.
                if (mat.emits_towards(sp.front_face)) {
                    const int li = c.lights.emitter_of(geom);
                    float w = 1.f;
                    if (!W.connect) {
                        if (!ws.specular[slot]) w = 0.f;  // merging finds it
                    } else if (len > 1 && li >= 0) {
                        const float pick = c.lights.pmf(uint32_t(li));
                        const float direct =
                            pick * c.lights.pdf_li(uint32_t(li), ws.p_prev[slot], sp.p, sp.ng) *
                            cos_in / d2;
                        float pdf_pos, pdf_dir;
                        c.lights.pdf_le(uint32_t(li), sp.ng, -d, pdf_pos, pdf_dir);
                        w = 1.f / (1.f + W.mis(direct) * m.dvcm +
                                   W.mis(pick * pdf_pos * pdf_dir) * m.dvc);
                    }
                    add(slot, c.layers.of(0, t), beta * mat.emission * W.strategy(0, t, w));
                }
                if (len >= c.max_segments || mat.bsdf.empty()) continue;

                const warp::Frame frame = sp.frame();
                const Vec3 wo = frame.to_local(-d);
                const BsdfContext ctx{sp.front_face, Transport::Radiance};
                const BsdfContext ictx{sp.front_face, Transport::Importance};
                // The vertex's continuation probability (Russian roulette) is part of every
                // density of sampling a direction here, either way.
                const float q = mat.bsdf.continuation();
                if (mat.bsdf.has_non_delta()) {
                    // s = 1: a light sample.
                    if (W.connect && !c.lights.empty()) {
                        float pick;
                        const uint32_t li = c.lights.select(rand(slot, depth, kDimSelect), pick);
                        LightSample ls;
                        if (c.lights.sample_li(
                                li, sp.p,
                                {rand(slot, depth, kDimLight), rand(slot, depth, kDimLight + 1)},
                                rand(slot, depth, kDimTriangle), ls) &&
                            mat.bsdf.side_allowed(ls.wi, sp.ng)) {
                            const Vec3 wi = frame.to_local(ls.wi);
                            const RGB f = mat.bsdf.f(wo, wi, ctx);
                            if (!f.is_black()) {
                                const Emitter& em = c.lights.emitter(li);
                                const float direct = pick * ls.pdf;
                                // A point or spot light's sample has density 1 in its delta
                                // measure; in solid angle, as the other strategies' densities
                                // are converted, it is d^2 (and Li carries the 1 / d^2).
                                const float direct_w =
                                    em.is_delta_position() ? direct * ls.dist * ls.dist : direct;
                                float pdf_pos, pdf_dir;
                                c.lights.pdf_le(li, ls.n_light, -ls.wi, pdf_pos, pdf_dir);
                                const float emit = pick * pdf_pos * pdf_dir;
                                const float cos_light = em.is_delta() || em.is_infinite()
                                                            ? 1.f
                                                            : std::fabs(dot(ls.n_light, ls.wi));
                                const float w_light =
                                    em.is_delta() ? 0.f
                                                  : W.mis(mat.bsdf.pdf(wo, wi, ctx) * q / direct);
                                const float w_camera =
                                    W.mis(emit * std::fabs(dot(ls.wi, sp.ng)) /
                                          (direct_w * cos_light)) *
                                    (W.vm_weight + m.dvcm +
                                     m.dvc * W.mis(mat.bsdf.pdf(wi, wo, ictx) * q));
                                const float w = W.strategy(1, t, 1.f / (w_light + 1.f + w_camera));
                                const RGB value = beta * f * ls.Li * (std::fabs(wi.z) * w / direct);
                                if (!value.is_black())
                                    push_shadow(shadow_ray_to(sp, ls), geom, sp, slot, value, 1, t,
                                                1);
                            }
                        }
                    }
                    // s >= 2: connections to the pixel's light path; then merges with every
                    // light vertex within the radius. On the kernel's materials queued for
                    // one batch of lobe pairs (join_batched), else evaluated here.
                    const bool batched = kernel_vertex(geom);
                    uint32_t vertex = 0;
                    if (batched) {
                        vertex = uint32_t(ws.vertices.size());
                        ws.vertices.push_back({slot, geom, t, q, beta, m, sp});
                    }
                    const uint32_t path = ws.path[slot];
                    if (W.connect)
                        for (uint32_t j = store.first[path]; j < store.first[path + 1]; ++j) {
                            if (lv.length[j] + len + 1 > c.max_segments) break;
                            const Vec3 to = lv.position(j) - sp.p;
                            const float dist2 = length_squared(to);
                            if (!(dist2 > 0.f)) continue;
                            const float dist = std::sqrt(dist2);
                            const Vec3 dir = to / dist;
                            // The camera end on the side its vertex was reached from, or behind
                            // it through a rough dielectric (the light end: light_end).
                            const float cos_c = std::fabs(dot(dir, sp.ng));
                            const bool front_c = dot(dir, sp.ng) > 0.f;
                            if (cos_c == 0.f || !(front_c || mat.bsdf.transmits_non_delta()))
                                continue;
                            const Vec3 dc = frame.to_local(dir);
                            const float cos_l = std::fabs(dot(dir, lv.ng[j]));
                            if (batched && !lv.in_medium(j) && cos_l != 0.f &&
                                dot(dir, lv.ng[j]) < 0.f && kernel_vertex(lv.geom[j])) {
                                const warp::Frame lf(lv.ns[j], lv.ss[j]);
                                const uint32_t cam_pair = ws.pairs.add(material_of(geom), wo, dc);
                                ws.pairs.add(material_of(lv.geom[j]), lf.to_local(lv.wo[j]),
                                             lf.to_local(-dir));
                                ws.connections.push_back(
                                    {vertex, j, cam_pair, dist2, cos_c, cos_l, std::fabs(dc.z)});
                                continue;
                            }
                            const RGB fc = mat.bsdf.f(wo, dc, ctx);
                            if (fc.is_black()) continue;
                            LobeEval le;
                            float ql, cos_lj;
                            if (!light_end(scene, lv, j, dir, le, ql, cos_lj)) continue;
                            const LobeEval ce{fc, mat.bsdf.pdf(wo, dc, ctx),
                                              mat.bsdf.pdf(dc, wo, ictx)};
                            const RGB value =
                                connection_value(W, m, beta, t, lv, j, ce, q, le, ql, dist2, cos_c,
                                                 cos_lj, std::fabs(dc.z));
                            if (!value.is_black())
                                push_connection(sp, geom, j, dist, value, slot, t);
                        }
                    if (W.merge) {
                        RGB sum{0.f};
                        store.merge_candidates(sp.p, [&](uint32_t j) {
                            if (lv.length[j] + len > c.max_segments || lv.in_medium(j)) return;
                            const Vec3 wl = frame.to_local(lv.wo[j]);
                            if (batched) {
                                ws.merges.push_back(
                                    {vertex, j, ws.pairs.add(material_of(geom), wo, wl)});
                                return;
                            }
                            const RGB f = mat.bsdf.f(wo, wl, ctx);
                            if (f.is_black()) return;
                            const LobeEval ce{f, mat.bsdf.pdf(wo, wl, ctx),
                                              mat.bsdf.pdf(wl, wo, ictx)};
                            sum += merge_term(W, m, lv, j, ce, q);
                        });
                        if (!batched) add(slot, c.layers.merges(), beta * sum * W.vm_norm);
                    }
                }

                // Onwards by sampling the BSDF.
                if (rand(slot, depth, kDimRoulette) >= q) continue;
                BsdfSample bs;
                if (!mat.bsdf.sample(
                        wo, rand(slot, depth, kDimBsdf),
                        {rand(slot, depth, kDimBsdf + 1), rand(slot, depth, kDimBsdf + 2)}, ctx,
                        bs))
                    continue;
                const Vec3 wi = frame.to_world(bs.wi);
                const float side = dot(wi, sp.ng);
                if ((bs.flags & kTransmission) ? side >= 0.f : side <= 0.f) continue;
                beta *= bs.f * (std::fabs(bs.wi.z) / (bs.pdf * q));
                if (beta.is_black()) continue;
                if (bs.is_delta()) {
                    m.scatter_delta(std::fabs(side), W);
                } else {
                    m.scatter(std::fabs(side), bs.pdf * q, mat.bsdf.pdf(bs.wi, wo, ictx) * q, W);
                    ws.specular[slot] = 0;
                }
                ws.p_prev[slot] = sp.p;
                if (media.on) {
                    media.medium[slot] = medium_after(scene, geom, sp, wi, media.medium[slot]);
                    media.from[slot] = sp.p;
                }
                ws.next.push(offset_origin(sp, wi), wi, 0.f, kInfinity, slot);
            }
            join_batched();
        },
        [&](uint32_t) { ws.joins.resolve(media.on, scene, c.accel, c.seed, stats, clock, add); });
}

}  // namespace foton
