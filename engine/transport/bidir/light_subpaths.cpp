#include "light_subpaths.h"

#include <algorithm>
#include <cmath>

#include "engine/core/rng.h"
#include "engine/core/warp.h"
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
        return rng::uniform(c.seed, kBidirLightStream, c.iteration * c.light_paths + first + slot,
                            dim);
    };
    ws.rays.clear();
    ws.shadow.clear();
    ws.shadow_value.clear();
    ws.shadow_pixel.clear();
    ws.shadow_layer.clear();
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
        ws.rays.push(er.origin, es.dir, 0.f, kInfinity, k);
    }
    // Not counted as samples: those are the camera subpaths' (one per pixel and iteration).
    stats.add(Stage::Generate, count, clock);

    const uint32_t max_length = c.max_segments - 1;  // a vertex needs a camera vertex after it
    run_wavefront(c.accel, ws.rays, ws.next, ws.hits, 0, stats, clock, [&](uint32_t depth) {
        for (std::size_t i = 0; i < ws.rays.size(); ++i) {
            const uint32_t geom = ws.hits.geom[i];
            if (geom == kNoHit) continue;
            const uint32_t slot = ws.rays.id[i];
            const Vec3 d = ws.rays.direction(i);
            const SurfacePoint sp = surface_at(c.scene, ws.rays, ws.hits, i);
            std::optional<Material> scratch;
            const Material& mat = c.scene.material_at(geom, sp.uv, scratch);
            SubpathMis& m = ws.mis[slot];
            const float cos_in = std::fabs(dot(d, sp.ng));
            if (cos_in == 0.f) continue;
            const uint16_t len = ++ws.length[slot];
            if (len == 1 && !ws.infinite[slot] && m.dvc > 0.f) {
                // An area light: next event estimation from here would pick its point with
                // pick * pdf_li (solid angle), times cos0 / d^2 as an area density; the d^2
                // cancels the recursion's.
                const Vec3& x0 = ws.origin[slot];
                const float cos0 = std::fabs(dot(ws.origin_n[slot], d));
                const float direct =
                    ws.pick[slot] * c.lights.pdf_li(ws.light[slot], sp.p, x0, ws.origin_n[slot]);
                m.dvcm = W.mis(direct * cos0 / ws.emit_pdf[slot]);
                m.arrive(-1.f, cos_in, W);
            } else {
                const float t = ws.hits.t[i];
                m.arrive(len == 1 && ws.infinite[slot] ? -1.f : t * t, cos_in, W);
            }
            if (mat.bsdf.empty() || len > max_length) continue;
            RGB& beta = ws.beta[slot];
            const warp::Frame frame(sp.ns);
            const Vec3 wl = -d;
            const Vec3 wo = frame.to_local(wl);
            const float adj = std::fabs(wo.z) / cos_in;
            const BsdfContext ctx{sp.front_face, Transport::Importance};
            const BsdfContext rctx{sp.front_face, Transport::Radiance};
            // The vertex's continuation probability (Russian roulette), in both directions'
            // densities here.
            const float q = mat.bsdf.continuation();

            if (mat.bsdf.has_non_delta()) {
                LightVertices& v = ws.local;
                v.px.push_back(sp.p.x), v.py.push_back(sp.p.y), v.pz.push_back(sp.p.z);
                v.ng.push_back(sp.ng), v.ns.push_back(sp.ns), v.wo.push_back(wl);
                v.beta.push_back(beta), v.adj.push_back(adj);
                v.dvcm.push_back(m.dvcm), v.dvc.push_back(m.dvc), v.dvm.push_back(m.dvm);
                v.length.push_back(len), v.front.push_back(sp.front_face);
                v.geom.push_back(geom), v.uv.push_back(sp.uv), v.path.push_back(first + slot);

                // t = 1: the vertex joined to the camera: the pinhole, or a point of the thin
                // lens (whose importance, per unit lens area, makes the same weight: the
                // lens' cosine and area cancel against its sampling density).
                const uint32_t lens_dim = kDimBounce + depth * kDimsPerBounce + 4;
                const Vec3 lens =
                    cam.lens_radius > 0.f
                        ? cam.lens_point({rand(slot, lens_dim), rand(slot, lens_dim + 1)})
                        : cam.eye;
                float fx, fy;
                if (W.connect && cam.project_through(lens, sp.p, fx, fy)) {
                    const Vec3 to = lens - sp.p;
                    const float dist2 = length_squared(to), dist = std::sqrt(dist2);
                    const Vec3 wc = to / dist;
                    const float cos_cam = -dot(wc, cam.w);
                    const float cos_sc = std::fabs(dot(wc, sp.ng));
                    const Vec3 wcl = frame.to_local(wc);
                    const RGB f = mat.bsdf.f(wo, wcl, ctx);
                    if (!f.is_black() && cos_cam > 0.f && mat.bsdf.side_allowed(wc, sp.ng) &&
                        cos_sc > 0.f) {
                        // The camera's density of this point per pixel sample, in area measure.
                        const float cam_pdf_a = cam.importance(cos_cam, 1.f) * cos_sc / dist2;
                        const float rev = mat.bsdf.pdf(wcl, wo, rctx) * q;
                        const float w_light = W.mis(cam_pdf_a / n_paths) *
                                              (W.vm_weight + m.dvcm + m.dvc * W.mis(rev));
                        const float w = W.strategy(int(len) + 1, 1, 1.f / (1.f + w_light));
                        const RGB value =
                            beta * f * (adj * cos_sc * cam.importance(cos_cam, dist) * w / n_paths);
                        if (!value.is_black()) {
                            ws.shadow.push(offset_origin(sp, wc), wc, 0.f, dist * (1.f - 1e-4f),
                                           slot);
                            ws.shadow_value.push_back(value);
                            ws.shadow_pixel.push_back(cam.film_pixel(fx, fy));
                            if (splat_layers)
                                ws.shadow_layer.push_back(c.layers.of(int(len) + 1, 1));
                        }
                    }
                }
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

    if (!ws.shadow.empty()) {
        c.accel.occluded(ws.shadow, ws.occluded, stats.trace);
        stats.shadow_rays += ws.shadow.size();
        stats.add(Stage::Occlusion, ws.shadow.size(), clock);
        for (std::size_t i = 0; i < ws.shadow.size(); ++i)
            if (!ws.occluded[i]) {
                splats.push_back({ws.shadow_pixel[i], ws.shadow_value[i]});
                if (splat_layers) splat_layers->push_back(ws.shadow_layer[i]);
            }
    }
}

}  // namespace foton
