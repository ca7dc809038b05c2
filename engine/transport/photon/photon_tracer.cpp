#include "photon_tracer.h"

#include <algorithm>
#include <cmath>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "engine/core/rng_streams.h"
#include "engine/core/thread_clock.h"
#include "engine/core/warp.h"
#include "engine/transport/common/camera_integrator.h"
#include "engine/transport/common/surface.h"
#include "engine/transport/common/wavefront.h"

namespace foton {

namespace {
constexpr uint32_t kPhotonChunk = 4096;
// Surfaces a shadow photon's line is followed through beyond its first hit.
constexpr int kShadowCrossings = 8;
}  // namespace

PhotonTracer::PhotonTracer(const Scene& scene, const Intersector& accel, const LightSet& lights,
                           uint64_t seed)
    : scene_(scene), accel_(accel), lights_(lights), seed_(seed) {}

float PhotonTracer::rand(uint64_t pass, uint64_t photon, uint32_t dim) const {
    return rng::uniform(seed_ + pass * 0x9e3779b97f4a7c15ull, kPhotonStream, photon, dim);
}

void PhotonTracer::trace(const PhotonPassSettings& s, uint64_t first, uint32_t count,
                         PhotonWorkspace& ws, PhotonMap& out, PhotonMap* shadow,
                         RenderStats& stats) const {
    StageClock clock;
    ws.rays.clear();
    ws.shadow.clear();
    ws.power.assign(count, RGB{0.f});
    ws.specular_only.assign(count, 1);
    ws.last_specular.assign(count, 0);
    ws.light.assign(count, 0);
    // The direction sample of photon i is point i of a Hammersley set over the pass, shifted
    // by one random offset per pass (Cranley–Patterson), so directions are stratified.
    const float shift_x = rand(s.pass, ~0ull, 0), shift_y = rand(s.pass, ~0ull, 1);
    const float inv_n = 1.f / float(s.emitted);
    for (uint32_t k = 0; k < count; ++k) {
        const uint64_t i = first + k;
        float ux = (float(i) + 0.5f) * inv_n + shift_x;
        float uy = radical_inverse2(uint32_t(i)) + shift_y;
        if (s.numbers) {
            ux = number(s, first, k, kPhotonDimDirection);
            uy = number(s, first, k, kPhotonDimDirection + 1);
        }
        ux -= std::floor(ux);
        uy -= std::floor(uy);
        EmittedRay er;
        if (!lights_.sample_ray(
                number(s, first, k, kPhotonDimLight),
                {number(s, first, k, kPhotonDimPos), number(s, first, k, kPhotonDimPos + 1)},
                {std::min(ux, 0x1.fffffep-1f), std::min(uy, 0x1.fffffep-1f)},
                number(s, first, k, kPhotonDimTriangle), er))
            continue;
        ws.light[k] = uint16_t(er.light);
        ws.power[k] = s.numbers ? er.beta : er.beta * inv_n;
        ws.rays.push(er.origin, er.emission.dir, 0.f, kInfinity, k);
    }
    stats.add(Stage::PhotonEmit, count, clock);

    // A photon's scattering (store, roulette, next direction) is the trace stage; the merge
    // of the chunks' photons is the store stage.
    const WavefrontStages stages{Stage::PhotonIntersect, Stage::PhotonTrace, nullptr};
    run_wavefront(
        accel_, ws.rays, ws.next, ws.hits, 0, s.max_depth, stats, clock,
        [&](uint32_t depth) {
            for (std::size_t r = 0; r < ws.rays.size(); ++r) {
                const uint32_t geom = ws.hits.geom[r];
                if (geom == kNoHit) continue;
                const uint32_t slot = ws.rays.id[r];
                const uint64_t i = first + slot;
                const Vec3 d = ws.rays.direction(r);
                const SurfacePoint sp = surface_at(scene_, ws.rays, ws.hits, r);
                std::optional<Material> scratch;
                const Material& m = scene_.material_at(geom, sp.tex(), scratch);
                if (m.bsdf.empty()) continue;
                RGB& power = ws.power[slot];
                if (m.bsdf.has_non_delta()) {
                    const bool caustic = ws.specular_only[slot] && depth > 0;
                    const uint8_t flags =
                        uint8_t((caustic ? kPhotonCaustic : 0) | (depth == 0 ? kPhotonDirect : 0) |
                                (depth > 0 && ws.last_specular[slot] ? kPhotonViaSpecular : 0));
                    // Stored with the importance map's probability q, its power over q.
                    const float q = s.importance ? s.importance->store_probability(sp.p) : 1.f;
                    if ((s.kind == PhotonMapKind::Global || caustic) &&
                        (q >= 1.f || rng::uniform(seed_ + s.pass * 0x9e3779b97f4a7c15ull,
                                                  kImportonStoreStream, i, depth) < q)) {
                        out.push(sp.p, q >= 1.f ? power : power * (1.f / q), -d, sp.ng, flags,
                                 ws.light[slot]);
                        if (s.stored_by) s.stored_by->push_back(slot);
                    }
                }
                if (depth == 0 && shadow && s.shadow_photons) {
                    // The photon's line beyond its first hit: every further surface is in shadow
                    // of this light there.
                    ws.shadow.rays.push(offset_origin(sp, d), d, 0.f, kInfinity,
                                        uint32_t(ws.shadow.power.size()));
                    ws.shadow.power.push_back(power);
                    ws.shadow.light.push_back(ws.light[slot]);
                }
                const warp::Frame frame = sp.frame();
                const Vec3 wl = -d;
                const Vec3 wo = frame.to_local(wl);
                const BsdfContext ctx{sp.front_face, Transport::Importance};
                const float wl_ng = std::fabs(dot(wl, sp.ng));
                if (wl_ng == 0.f) continue;
                const float adj = std::fabs(wo.z) / wl_ng;
                const uint32_t dim = kPhotonDimFirstBounce + depth * kPhotonDimsPerBounce;
                BsdfSample bs;
                // A caustic pass follows only L S+ paths: its photons continue through the delta
                // lobes alone (the sample then carries only their share of the throughput).
                const uint8_t only = s.kind == PhotonMapKind::Caustic ? uint8_t(kSpecular) : 0xff;
                if (!m.bsdf.sample(
                        wo, number(s, first, slot, dim),
                        {number(s, first, slot, dim + 1), number(s, first, slot, dim + 2)}, ctx, bs,
                        only))
                    continue;
                const Vec3 wi = frame.to_world(bs.wi);
                const float side = dot(wi, sp.ng);
                if ((bs.flags & kTransmission) ? side >= 0.f : side <= 0.f) continue;
                RGB w = bs.f * (adj * std::fabs(side) / bs.pdf);
                const float q = std::min(1.f, w.max_component());
                if (!(q > 0.f) || number(s, first, slot, dim + 3) >= q) continue;
                if (!s.unscaled_roulette) power *= w * (1.f / q);
                if (!bs.is_delta()) ws.specular_only[slot] = 0;
                ws.last_specular[slot] = uint8_t(bs.is_delta());
                ws.next.push(offset_origin(sp, wi), wi, 0.f, kInfinity, slot);
            }
            if (depth == 0 && !ws.shadow.rays.empty())
                trace_shadow_lines(ws.shadow, *shadow, stats);
        },
        [](uint32_t) {}, stages);
}

void PhotonTracer::trace_shadow_lines(ShadowLineWork& w, PhotonMap& shadow,
                                      RenderStats& stats) const {
    for (int crossing = 0; crossing < kShadowCrossings && !w.rays.empty(); ++crossing) {
        accel_.intersect(w.rays, w.hits, stats.trace);
        w.next.clear();
        for (std::size_t r = 0; r < w.rays.size(); ++r) {
            if (w.hits.geom[r] == kNoHit) continue;
            const SurfacePoint q = surface_at(scene_, w.rays, w.hits, r);
            const Vec3 d = w.rays.direction(r);
            if (scene_.material_of(w.hits.geom[r]).bsdf.has_non_delta())
                w.found.push_back({w.rays.id[r], q.p, q.ng, d});
            w.next.push(offset_origin(q, d), d, 0.f, kInfinity, w.rays.id[r]);
        }
        std::swap(w.rays, w.next);
    }
    // Found crossing by crossing; stored line by line, each line's in crossing order.
    std::stable_sort(w.found.begin(), w.found.end(),
                     [](const ShadowLineWork::Crossing& a, const ShadowLineWork::Crossing& b) {
                         return a.line < b.line;
                     });
    for (const ShadowLineWork::Crossing& c : w.found)
        shadow.push(c.p, w.power[c.line] * -1.f, -c.dir, c.ng, kPhotonShadow, w.light[c.line]);
    w.clear();
}

PhotonMap PhotonTracer::run(const PhotonPassSettings& s, RenderStats& stats, PhotonMap* shadow,
                            const ProgressTask* task, const Cluster* cluster) const {
    const std::size_t chunks = std::size_t((s.emitted + kPhotonChunk - 1) / kPhotonChunk);
    const Cluster& ranks = cluster_or_solo(cluster);
    const Share mine = share_of(chunks, ranks);
    std::vector<PhotonMap> parts(chunks), shadow_parts(shadow ? chunks : 0);
    tbb::enumerable_thread_specific<PhotonWorkspace> workspaces;
    tbb::enumerable_thread_specific<RenderStats> st;
    // The chunks' thread time goes to the graph node that runs this pass (thread_clock.h).
    BusyTime* const busy = ThreadClock::for_chunks();
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(mine.begin, mine.end, 1),
        [&](const tbb::blocked_range<std::size_t>& r) {
            const ThreadClock clock(busy);
            PhotonWorkspace& ws = workspaces.local();
            RenderStats& local = st.local();
            for (std::size_t c = r.begin(); c != r.end(); ++c) {
                if (s.cancel && s.cancel->load(std::memory_order_relaxed)) return;
                const uint64_t first = uint64_t(c) * kPhotonChunk;
                const uint32_t n = uint32_t(std::min<uint64_t>(kPhotonChunk, s.emitted - first));
                trace(s, first, n, ws, parts[c], shadow ? &shadow_parts[c] : nullptr, local);
                if (task) task->advance(n);
            }
        });
    StageClock clock;
    std::size_t total = 0;
    for (const PhotonMap& p : parts) total += p.size();
    PhotonMap map;
    map.reserve(total);
    for (const PhotonMap& p : parts) map.append(p);
    PhotonMap shadows;
    if (shadow)
        for (const PhotonMap& p : shadow_parts) shadows.append(p);
    if (ranks.distributed()) {
        map.all_gather(ranks);
        if (shadow) shadows.all_gather(ranks);
    }
    if (shadow) shadow->append(shadows);
    for (const RenderStats& l : st) stats.merge(l);
    stats.add(Stage::PhotonStore, total, clock);
    return map;
}

}  // namespace foton
