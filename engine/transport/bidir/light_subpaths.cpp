#include "light_subpaths.h"

#include <algorithm>
#include <cmath>

#include "engine/core/rng.h"
#include "engine/core/warp.h"
#include "engine/scene/medium.h"
#include "engine/transport/common/film_splats.h"
#include "engine/transport/common/surface.h"
#include "engine/transport/common/wavefront.h"

namespace foton {

namespace {
// Random dimensions: light choice, position (2), direction (2), triangle; then per bounce
// the BSDF lobe and direction (2), Russian roulette and the lens point of the join to the
// camera (2).
constexpr uint32_t kDimSelect = 0, kDimPos = 1, kDimDir = 3, kDimTriangle = 5, kDimBounce = 8,
                   kDimsPerBounce = 6;
}  // namespace

void trace_light_subpaths(const VcmContext& c, uint32_t first, uint32_t count,
                          LightSubpathWorkspace& ws, LightVertices& out, std::vector<Splat>& splats,
                          std::vector<uint32_t>* splat_layers, RenderStats& stats) {
    const Camera& cam = c.scene.camera;
    const VcmWeights& W = c.weights;
    const float n_paths = float(c.light_paths);
    StageClock clock;
    auto rand = [&](uint32_t slot, uint32_t dim) {
        if (c.primary) return c.primary[first + slot]->get(primary_light_dim(dim));
        return rng::uniform(c.seed, kBidirLightStream, c.iteration * c.light_paths + first + slot,
                            dim);
    };
    ws.rays.clear();
    ws.joins.clear();
    ws.shadow_at.clear();
    ws.local.clear();
    ws.beta.assign(count, RGB{0.f});
    ws.mis.assign(count, {});
    ws.length.assign(count, 0);
    ws.emit_pdf.assign(count, 0.f);
    ws.pick.assign(count, 0.f);
    ws.light.assign(count, 0);
    ws.origin.assign(count, Vec3{});
    ws.origin_n.assign(count, Vec3{});
    ws.infinite.assign(count, 0);
    SubpathMedia& media = ws.media;
    media.reset(c.media, c.seed, kBidirLightMediumStream, count);
    auto path_key = [&](uint32_t slot) { return c.iteration * c.light_paths + first + slot; };
    const Scene& scene = c.scene;

    for (uint32_t k = 0; k < count; ++k) {
        EmittedRay er;
        if (!c.lights.sample_ray(rand(k, kDimSelect), {rand(k, kDimPos), rand(k, kDimPos + 1)},
                                 {rand(k, kDimDir), rand(k, kDimDir + 1)}, rand(k, kDimTriangle),
                                 er))
            continue;
        const Emitter& em = c.lights.emitter(er.light);
        const EmissionSample& es = er.emission;
        const float emit_pdf = er.pmf * es.pdf_pos * es.pdf_dir;
        const bool area = !em.is_delta() && !em.is_infinite();
        SubpathMis& m = ws.mis[k];
        // How next event estimation would have found the light's point: for an area light
        // it depends on the receiving point and is set at the first hit.
        if (!area) {
            const float direct =
                em.type == EmitterType::Environment ? c.lights.environment_pdf(-es.dir) : er.pmf;
            m.dvcm = W.mis(direct / emit_pdf);
        }
        if (!em.is_delta()) {
            const float cos0 = area ? std::fabs(dot(es.n, es.dir)) : 1.f;
            m.dvc = W.mis(cos0 / emit_pdf);
        }
        m.dvm = m.dvc * W.vc_weight;
        ws.beta[k] = er.beta;
        ws.emit_pdf[k] = emit_pdf;
        ws.pick[k] = er.pmf;
        ws.light[k] = er.light;
        ws.origin[k] = es.p;
        ws.origin_n[k] = es.n;
        ws.infinite[k] = em.is_infinite();
        if (media.on) {
            media.medium[k] = (*c.light_medium)[er.light];
            media.key[k] = path_key(k);
            media.from[k] = es.p;
        }
        ws.rays.push(er.origin, es.dir, 0.f, kInfinity, k);
    }
    // Not counted as samples: those are the camera subpaths' (one per pixel and iteration).
    stats.add(Stage::Generate, count, clock);

    const uint32_t max_length = c.max_segments - 1;  // a vertex needs a camera vertex after it
    // The MIS sums on arriving at vertex p of path `slot` along d (|cos| cos_in there) over a
    // segment of squared length d2.
    auto arrive = [&](uint32_t slot, const Vec3& p, const Vec3& d, float cos_in, float d2,
                      uint16_t len) {
        SubpathMis& m = ws.mis[slot];
        if (len == 1 && !ws.infinite[slot] && m.dvc > 0.f) {
            // An area light: next event estimation from here would pick its point with
            // pick * pdf_li (solid angle), times cos0 / d^2 as an area density; the d^2
            // cancels the recursion's.
            const Vec3& x0 = ws.origin[slot];
            const float cos0 = std::fabs(dot(ws.origin_n[slot], d));
            const float direct =
                ws.pick[slot] * c.lights.pdf_li(ws.light[slot], p, x0, ws.origin_n[slot]);
            m.dvcm = W.mis(direct * cos0 / ws.emit_pdf[slot]);
            m.arrive(-1.f, cos_in, W);
        } else {
            m.arrive(len == 1 && ws.infinite[slot] ? -1.f : d2, cos_in, W);
        }
    };
    // Stores the vertex (sp null: a medium vertex in `medium`).
    auto store = [&](uint32_t slot, uint16_t len, const Vec3& p, const SurfacePoint* sp,
                     uint32_t geom, int32_t medium, const Vec3& wl, float adj) {
        const SubpathMis& m = ws.mis[slot];
        LightVertices& v = ws.local;
        v.px.push_back(p.x), v.py.push_back(p.y), v.pz.push_back(p.z);
        v.ng.push_back(sp ? sp->ng : Vec3{}), v.ns.push_back(sp ? sp->ns : Vec3{});
        v.ss.push_back(sp ? sp->ss : Vec3{});
        v.wo.push_back(wl), v.beta.push_back(ws.beta[slot]), v.adj.push_back(adj);
        v.dvcm.push_back(m.dvcm), v.dvc.push_back(m.dvc), v.dvm.push_back(m.dvm);
        v.length.push_back(len), v.front.push_back(sp ? sp->front_face : 1);
        v.geom.push_back(geom), v.uv.push_back(sp ? sp->uv : Point2{});
        v.path.push_back(first + slot), v.medium.push_back(sp ? kNoMedium : medium);
    };
    // The vertex's join to the camera (t = 1): the pinhole, or a point of the thin lens
    // (whose importance, per unit lens area, makes the same weight: the lens' cosine and area
    // cancel against its sampling density). f(wc, value, rev) gives the BSDF's or phase
    // function's value towards the camera and the reverse density, false where it has none.
    auto join_camera = [&](uint32_t slot, uint32_t depth, uint16_t len, const Vec3& p,
                           const SurfacePoint* sp, uint32_t geom, int32_t medium, float adj,
                           auto&& f) {
        const uint32_t lens_dim = kDimBounce + depth * kDimsPerBounce + 4;
        const Vec3 lens = cam.lens_radius > 0.f
                              ? cam.lens_point({rand(slot, lens_dim), rand(slot, lens_dim + 1)})
                              : cam.eye;
        float fx, fy;
        if (!W.connect || !cam.project_through(lens, p, fx, fy, scene.film.filter.margin())) return;
        const Vec3 to = lens - p;
        const float dist2 = length_squared(to), dist = std::sqrt(dist2);
        const Vec3 wc = to / dist;
        const float cos_cam = -dot(wc, cam.w);
        const float cos_sc = sp ? std::fabs(dot(wc, sp->ng)) : 1.f;
        RGB f_value;
        float rev = 0.f;
        if (!(cos_cam > 0.f) || !(cos_sc > 0.f) || !f(wc, f_value, rev)) return;
        // The camera's density of this point per pixel sample, in area measure.
        const SubpathMis& m = ws.mis[slot];
        const float cam_pdf_a = cam.importance(cos_cam, 1.f) * cos_sc / dist2;
        const float w_light =
            W.mis(cam_pdf_a / n_paths) * (W.merge_at(!sp) + m.dvcm + m.dvc * W.mis(rev));
        const float w = W.strategy(int(len) + 1, 1, 1.f / (1.f + w_light));
        const RGB value =
            ws.beta[slot] * f_value * (adj * cos_sc * cam.importance(cos_cam, dist) * w / n_paths);
        if (value.is_black()) return;
        const int32_t med =
            media.on && sp ? medium_after(scene, geom, *sp, wc, media.medium[slot]) : medium;
        ws.joins.push(media.on, {sp ? offset_origin(*sp, wc) : p, wc, dist * (1.f - 1e-4f)}, med,
                      uint32_t(ws.shadow_at.size()), value,
                      c.primary      ? first + slot
                      : splat_layers ? c.layers.of(int(len) + 1, 1)
                                     : 0u,
                      rng::hash(path_key(slot), 0x11, len, 0));
        ws.shadow_at.push_back({fx, fy});
    };
    // A flight of path `slot` scattered at p in medium mi, the ray having come along d.
    auto medium_vertex = [&](uint32_t slot, uint32_t depth, const Vec3& p, const Vec3& d,
                             int32_t mi) {
        const uint16_t len = ++ws.length[slot];
        arrive(slot, p, d, 1.f, length_squared(p - media.from[slot]), len);
        if (len > max_length) return;
        const float g = scene.media[std::size_t(mi)].g;
        const Vec3 wl = -d;
        store(slot, len, p, nullptr, kNoHit, mi, wl, 1.f);
        join_camera(slot, depth, len, p, nullptr, kNoHit, mi, 1.f,
                    [&](const Vec3& wc, RGB& value, float& rev) {
                        rev = henyey_greenstein(dot(wl, wc), g);
                        value = RGB{rev};
                        return true;
                    });
        if (len >= max_length) return;
        // The phase function is its own sampling density: beta stays.
        const uint32_t dim = kDimBounce + depth * kDimsPerBounce;
        Vec3 wi;
        const float pdf =
            sample_henyey_greenstein(wl, g, {rand(slot, dim + 1), rand(slot, dim + 2)}, wi);
        ws.mis[slot].scatter_medium(pdf, pdf, W);
        media.from[slot] = p;
        ws.next.push(p, wi, 0.f, kInfinity, slot);
    };

    run_wavefront(c.accel, ws.rays, ws.next, ws.hits, 0, stats, clock, [&](uint32_t depth) {
        if (media.on) media.track(scene, ws.rays, ws.hits, ws.beta, c.settings.simd_shading);
        for (std::size_t i = 0; i < ws.rays.size(); ++i) {
            const uint32_t slot = ws.rays.id[i];
            const Vec3 d = ws.rays.direction(i);
            RGB& beta = ws.beta[slot];
            float t_scatter = 0.f;
            const SubpathMedia::FlightEnd end =
                media.fly(scene, ws.rays, ws.hits, i, beta, t_scatter);
            if (end == SubpathMedia::FlightEnd::Gone) continue;
            if (end == SubpathMedia::FlightEnd::Scattered) {
                medium_vertex(slot, depth, ws.rays.origin(i) + d * t_scatter, d,
                              media.medium[slot]);
                continue;
            }
            const uint32_t geom = ws.hits.geom[i];
            if (geom == kNoHit) continue;
            const SurfacePoint sp = surface_at(scene, ws.rays, ws.hits, i);
            std::optional<Material> scratch;
            const Material& mat = scene.material_at(geom, sp.tex(), scratch);
            if (media.on && mat.is_interface) {
                cross_interface(scene, geom, sp, d, slot, media.medium[slot], media.crossings[slot],
                                ws.next);
                continue;
            }
            SubpathMis& m = ws.mis[slot];
            const float cos_in = std::fabs(dot(d, sp.ng));
            if (cos_in == 0.f) continue;
            const uint16_t len = ++ws.length[slot];
            const float t = ws.hits.t[i];
            arrive(slot, sp.p, d, cos_in,
                   media.on ? length_squared(sp.p - media.from[slot]) : t * t, len);
            if (mat.bsdf.empty() || len > max_length) continue;
            const warp::Frame frame = sp.frame();
            const Vec3 wl = -d;
            const Vec3 wo = frame.to_local(wl);
            const float adj = std::fabs(wo.z) / cos_in;
            const BsdfContext ctx{sp.front_face, Transport::Importance};
            const BsdfContext rctx{sp.front_face, Transport::Radiance};
            // The vertex's continuation probability (Russian roulette), in both directions'
            // densities here.
            const float q = mat.bsdf.continuation();

            if (mat.bsdf.has_non_delta()) {
                store(slot, len, sp.p, &sp, geom, kNoMedium, wl, adj);
                join_camera(slot, depth, len, sp.p, &sp, geom, kNoMedium, adj,
                            [&](const Vec3& wc, RGB& value, float& rev) {
                                const Vec3 wcl = frame.to_local(wc);
                                value = mat.bsdf.f(wo, wcl, ctx);
                                if (value.is_black() || !mat.bsdf.side_allowed(wc, sp.ng))
                                    return false;
                                rev = mat.bsdf.pdf(wcl, wo, rctx) * q;
                                return true;
                            });
            }
            if (len >= max_length) continue;
            const uint32_t dim = kDimBounce + depth * kDimsPerBounce;
            if (rand(slot, dim + 3) >= q) continue;
            BsdfSample bs;
            if (!mat.bsdf.sample(wo, rand(slot, dim), {rand(slot, dim + 1), rand(slot, dim + 2)},
                                 ctx, bs))
                continue;
            const Vec3 wi = frame.to_world(bs.wi);
            const float side = dot(wi, sp.ng);
            if ((bs.flags & kTransmission) ? side >= 0.f : side <= 0.f) continue;
            const float cos_out = std::fabs(side);
            beta *= bs.f * (adj * cos_out / (bs.pdf * q));
            if (beta.is_black()) continue;
            if (bs.is_delta())
                m.scatter_delta(cos_out, W);
            else
                m.scatter(cos_out, bs.pdf * q, mat.bsdf.pdf(bs.wi, wo, rctx) * q, W);
            if (media.on) {
                media.medium[slot] = medium_after(scene, geom, sp, wi, media.medium[slot]);
                media.from[slot] = sp.p;
            }
            ws.next.push(offset_origin(sp, wi), wi, 0.f, kInfinity, slot);
        }
    });

    // The chunk's vertices, path by path (a stable sort by path of the wavefront order,
    // which is by length within a path).
    const LightVertices& v = ws.local;
    std::vector<uint32_t> order(v.size());
    for (uint32_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(),
                     [&](uint32_t a, uint32_t b) { return v.path[a] < v.path[b]; });
    for (uint32_t i : order) out.push(v, i);

    ws.joins.resolve(media.on, scene, c.accel, c.seed, stats, clock,
                     [&](uint32_t at, uint32_t layer, const RGB& value) {
                         push_splats(scene.film, ws.shadow_at[at], value, splats);
                         // Every pixel the filter spread it to keeps its strategy's layer.
                         if (splat_layers) splat_layers->resize(splats.size(), layer);
                     });
}

}  // namespace foton
