#pragma once
// Rays leaving a diffuse point to sample its incident light (final-gather rays, a cache
// record's hemisphere rays), traced as batches through delta lobes: at a mirror or glass
// surface both branches are followed deterministically, up to kGatherSpecularDepth
// bounces; at every hit with non-delta lobes the caller's `at_hit` says what the ray sees
// there. Emission is never counted: the diffuse point's direct light comes from its own
// light sample. So is the environment (an emitter like the others): only the thesis'
// background colour, which no light sample finds, is passed to at_miss.
#include <limits>
#include <utility>
#include <vector>

#include "engine/accel/intersector.h"
#include "engine/core/ray_batch.h"
#include "engine/core/rgb.h"
#include "engine/core/warp.h"
#include "engine/scene/scene.h"
#include "engine/transport/common/surface.h"
#include "engine/transport/common/wavefront.h"

namespace foton {

inline constexpr uint32_t kGatherSpecularDepth = 4;

struct GatherBuffers {
    RayBatch rays, next;                   // ray id = the slot of `out` it adds to
    std::vector<RGB> weight, weight_next;  // per ray
    HitBatch hits;
    void clear() {
        rays.clear();
        weight.clear();
    }
    void push(const Vec3& o, const Vec3& d, float tmax, uint32_t slot, const RGB& w) {
        rays.push(o, d, 0.f, tmax, slot);
        weight.push_back(w);
    }
};

// Traces b.rays as a wavefront (common/wavefront.h); a miss calls at_miss(slot, weight *
// background); at a hit with non-delta lobes at_hit(slot, weight, sp, material, direction) is
// called. With `first_dist`, the first segment's length (infinite for a miss) goes to
// first_dist[slot]. Returns the rays traced.
template <class AtHit, class AtMiss>
std::size_t trace_gather(const Scene& scene, const Intersector& accel, GatherBuffers& b,
                         float* first_dist, RenderStats& stats, AtHit&& at_hit, AtMiss&& at_miss) {
    std::size_t traced = 0;
    StageClock unused;  // the caller times the gather as a whole
    const WavefrontStages stages{Stage::FinalGather, Stage::FinalGather, nullptr, false};
    run_wavefront(
        accel, b.rays, b.next, b.hits, 0, std::numeric_limits<uint32_t>::max(), stats, unused,
        [&](uint32_t depth) {
            traced += b.rays.size();
            b.weight_next.clear();
            for (std::size_t i = 0; i < b.rays.size(); ++i) {
                const uint32_t slot = b.rays.id[i];
                const RGB& w = b.weight[i];
                const uint32_t geom = b.hits.geom[i];
                if (depth == 0 && first_dist)
                    first_dist[slot] = geom == kNoHit ? kInfinity : b.hits.t[i];
                if (geom == kNoHit) {
                    if (!scene.environment) at_miss(slot, w * scene.background);
                    continue;
                }
                const Vec3 d = b.rays.direction(i);
                const SurfacePoint sp = surface_at(scene, b.rays, b.hits, i);
                std::optional<Material> scratch;
                const Material& m = scene.material_at(geom, sp.uv, scratch);
                if (m.bsdf.empty()) continue;
                // The non-delta lobes by the caller, the delta ones followed below: both
                // parts are taken whole, so neither is reweighted.
                if (m.bsdf.has_non_delta()) at_hit(slot, w, sp, m, d);
                if (m.bsdf.has_delta() && depth < kGatherSpecularDepth) {
                    const warp::Frame frame = sp.frame();
                    const Vec3 wo = frame.to_local(-d);
                    const BsdfContext ctx{sp.front_face, Transport::Radiance};
                    Vec3 dirs[Bsdf::kMaxLobes * 2];
                    RGB dw[Bsdf::kMaxLobes * 2];
                    const int k =
                        m.bsdf.specular_directions(wo, ctx, dirs, dw, Bsdf::kMaxLobes * 2);
                    for (int j = 0; j < k; ++j) {
                        const RGB wj = w * dw[j];
                        if (wj.max_component() < 1e-4f) continue;
                        const Vec3 wi = frame.to_world(dirs[j]);
                        b.next.push(offset_origin(sp, wi), wi, 0.f, kInfinity, slot);
                        b.weight_next.push_back(wj);
                    }
                }
            }
        },
        [&](uint32_t) { std::swap(b.weight, b.weight_next); }, stages);
    return traced;
}

// The same, a miss adding weight * background to out[slot].
template <class AtHit>
std::size_t trace_gather(const Scene& scene, const Intersector& accel, GatherBuffers& b,
                         std::vector<RGB>& out, float* first_dist, RenderStats& stats,
                         AtHit&& at_hit) {
    return trace_gather(scene, accel, b, first_dist, stats, std::forward<AtHit>(at_hit),
                        [&](uint32_t slot, const RGB& v) { out[slot] += v; });
}

}  // namespace foton
