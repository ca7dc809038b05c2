#include "volume_photons.h"

#include <algorithm>
#include <cmath>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "engine/core/rng.h"
#include "engine/core/rng_streams.h"
#include "engine/core/sampler.h"
#include "engine/core/thread_clock.h"
#include "engine/core/warp.h"
#include "engine/transport/common/medium_locate.h"
#include "engine/transport/common/medium_shadow.h"
#include "engine/transport/common/medium_tracking.h"
#include "engine/transport/common/surface.h"
#include "grid_flights.h"

namespace foton {

namespace {
constexpr uint32_t kChunk = 4096;
}  // namespace

struct VolumePhotonTracer::Work {
    RayBatch rays, next;
    HitBatch hits;
    std::vector<RGB> power;
    std::vector<int32_t> medium;
    std::vector<uint32_t> bounces, crossings, draws;
    std::vector<uint16_t> light;
    GridFlights flights;  // a round's flights through grid media, as one batch
    std::vector<int32_t> flight_of;
};

VolumePhotonTracer::VolumePhotonTracer(const Scene& scene, const Intersector& accel,
                                       const LightSet& lights, uint64_t seed)
    : scene_(scene),
      accel_(accel),
      lights_(lights),
      seed_(seed),
      light_medium_(light_media(scene, accel, lights)) {}

void VolumePhotonTracer::trace(uint64_t pass, uint64_t emitted, uint64_t first, uint32_t count,
                               uint32_t max_depth, Work& ws, VolumePhotonMaps& out,
                               RenderStats& stats) const {
    StageClock clock;
    const uint64_t prefix =
        rng::stream_prefix(seed_ + pass * 0x9e3779b97f4a7c15ull, kVolumePhotonStream);
    ws.rays.clear();
    ws.power.assign(count, RGB{0.f});
    ws.medium.assign(count, kNoMedium);
    ws.bounces.assign(count, 0);
    ws.crossings.assign(count, 0);
    ws.draws.assign(count, 8);  // numbers 0..7 place the emission
    ws.light.assign(count, 0);
    auto u = [&](uint32_t slot) {
        return rng::uniform_from(prefix, first + slot, ws.draws[slot]++);
    };
    // Directions stratified over the pass as photon mapping's are (a shifted Hammersley set).
    const float shift_x = rng::uniform_from(prefix, ~0ull, 0),
                shift_y = rng::uniform_from(prefix, ~0ull, 1);
    const float inv_n = 1.f / float(emitted);
    for (uint32_t k = 0; k < count; ++k) {
        const uint64_t i = first + k;
        float ux = (float(i) + 0.5f) * inv_n + shift_x;
        float uy = radical_inverse2(uint32_t(i)) + shift_y;
        ux -= std::floor(ux);
        uy -= std::floor(uy);
        EmittedRay er;
        if (!lights_.sample_ray(rng::uniform_from(prefix, i, 0),
                                {rng::uniform_from(prefix, i, 1), rng::uniform_from(prefix, i, 2)},
                                {std::min(ux, 0x1.fffffep-1f), std::min(uy, 0x1.fffffep-1f)},
                                rng::uniform_from(prefix, i, 3), er))
            continue;
        ws.light[k] = uint16_t(er.light);
        ws.power[k] = er.beta * inv_n;
        ws.medium[k] = light_medium_[er.light];
        ws.rays.push(er.origin, er.emission.dir, 0.f, kInfinity, k);
    }
    stats.add(Stage::PhotonEmit, count, clock);
    for (uint32_t round = 0; !ws.rays.empty(); ++round) {
        accel_.intersect(ws.rays, ws.hits, stats.trace);
        stats.add(Stage::PhotonIntersect, ws.rays.size(), clock);
        ws.next.clear();
        // The round's flights through grid media as one batch (grid_flights.h).
        ws.flights.track_batch(scene_, ws.rays, ws.hits, ws.medium, ws.power, true, ws.flight_of,
                               u);
        for (std::size_t r = 0; r < ws.rays.size(); ++r) {
            const uint32_t slot = ws.rays.id[r];
            const uint32_t geom = ws.hits.geom[r];
            const Vec3 d = ws.rays.direction(r);
            RGB& power = ws.power[slot];
            // Russian roulette on a continuation's weight w: survive with max(w), at most 1.
            auto survive = [&](const RGB& w) {
                const float q = std::min(1.f, w.max_component());
                if (!(q > 0.f) || u(slot) >= q) return false;
                power *= w * (1.f / q);
                return true;
            };
            if (const int32_t mi = ws.medium[slot]; mi != kNoMedium) {
                const Medium& med = scene_.media[std::size_t(mi)];
                const FreeFlight f =
                    flight_of_entry(scene_, ws.flights, ws.flight_of, ws.rays, ws.hits, r, mi,
                                    power, [&] { return u(slot); });
                if (f.event == FreeFlight::Event::Absorb) continue;
                if (f.event == FreeFlight::Event::Scatter) {
                    const Vec3 p = ws.rays.origin(r) + d * f.t;
                    // Straight from the light: single scattering, which next event
                    // estimation can take instead.
                    out.volume.push(p, power * f.weight, -d, -d,
                                    ws.bounces[slot] == 0 ? kPhotonDirect : 0, ws.light[slot]);
                    if (++ws.bounces[slot] >= max_depth || !survive(f.weight)) continue;
                    Vec3 wi;
                    sample_henyey_greenstein(-d, med.g, {u(slot), u(slot)}, wi);
                    ws.next.push(p, wi, 0.f, kInfinity, slot);
                    continue;
                }
                power *= f.weight;
            }
            if (geom == kNoHit) continue;
            const SurfacePoint sp = surface_at(scene_, ws.rays, ws.hits, r);
            std::optional<Material> scratch;
            const Material& m = scene_.material_at(geom, sp.tex(), scratch);
            if (m.is_interface) {
                cross_interface(scene_, geom, sp, d, slot, ws.medium[slot], ws.crossings[slot],
                                ws.next);
                continue;
            }
            if (m.bsdf.empty()) continue;
            if (m.bsdf.has_non_delta())
                out.surface.push(sp.p, power, -d, sp.ng, ws.bounces[slot] == 0 ? kPhotonDirect : 0,
                                 ws.light[slot]);
            if (++ws.bounces[slot] >= max_depth) continue;
            const warp::Frame frame = sp.frame();
            const Vec3 wo = frame.to_local(-d);
            const BsdfContext ctx{sp.front_face, Transport::Importance};
            const float wl_ng = std::fabs(dot(d, sp.ng));
            if (wl_ng == 0.f) continue;
            BsdfSample bs;
            // Drawn in a fixed order: function arguments are evaluated in any.
            const float u0 = u(slot), u1 = u(slot), u2 = u(slot);
            if (!m.bsdf.sample(wo, u0, {u1, u2}, ctx, bs)) continue;
            const Vec3 wi = frame.to_world(bs.wi);
            const float side = dot(wi, sp.ng);
            if ((bs.flags & kTransmission) ? side >= 0.f : side <= 0.f) continue;
            // Veach's adjoint factor for shading normals, as photon mapping's tracer has it.
            const RGB w = bs.f * (std::fabs(wo.z) / wl_ng * std::fabs(side) / bs.pdf);
            if (!survive(w)) continue;
            ws.medium[slot] = medium_after(scene_, geom, sp, wi, ws.medium[slot]);
            ws.next.push(offset_origin(sp, wi), wi, 0.f, kInfinity, slot);
        }
        stats.add(Stage::PhotonTrace, ws.rays.size(), clock);
        std::swap(ws.rays, ws.next);
    }
}

VolumePhotonMaps VolumePhotonTracer::run(uint64_t pass, uint64_t emitted, uint32_t max_depth,
                                         RenderStats& stats, const Cluster* cluster,
                                         const std::atomic<bool>* cancel) const {
    const std::size_t chunks = std::size_t((emitted + kChunk - 1) / kChunk);
    const Cluster& ranks = cluster_or_solo(cluster);
    const Share mine = share_of(chunks, ranks);
    std::vector<VolumePhotonMaps> parts(chunks);
    tbb::enumerable_thread_specific<Work> workspaces;
    tbb::enumerable_thread_specific<RenderStats> st;
    BusyTime* const busy = ThreadClock::for_chunks();
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(mine.begin, mine.end, 1),
        [&](const tbb::blocked_range<std::size_t>& r) {
            const ThreadClock clock(busy);
            for (std::size_t c = r.begin(); c != r.end(); ++c) {
                if (cancel && cancel->load(std::memory_order_relaxed)) return;
                const uint64_t first = uint64_t(c) * kChunk;
                const uint32_t n = uint32_t(std::min<uint64_t>(kChunk, emitted - first));
                trace(pass, emitted, first, n, max_depth, workspaces.local(), parts[c], st.local());
            }
        });
    StageClock clock;
    VolumePhotonMaps maps;
    for (const VolumePhotonMaps& p : parts) {
        maps.surface.append(p.surface);
        maps.volume.append(p.volume);
    }
    if (ranks.distributed()) {
        maps.surface.all_gather(ranks);
        maps.volume.all_gather(ranks);
    }
    for (const RenderStats& l : st) stats.merge(l);
    stats.add(Stage::PhotonStore, maps.surface.size() + maps.volume.size(), clock);
    return maps;
}

}  // namespace foton
