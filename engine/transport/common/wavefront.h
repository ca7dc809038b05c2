#pragma once
// The wavefront loop every batch tracer runs (camera paths, light paths, photons): intersect
// the live rays as one batch, shade every hit (which may queue one continuation ray into
// `next` with the same slot id), then swap; `after_shade` runs between shading and the swap
// (the camera paths test their shadow rays there). Each step reports to its stage.
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include "engine/accel/intersector.h"
#include "engine/core/ray_batch.h"
#include "engine/core/rgb.h"
#include "engine/core/stats.h"

namespace foton {

// The buffers of a wavefront that tests shadow rays in batches: the live rays and the next
// bounce's, their hits, the shadow rays with the value each adds if unoccluded, and the
// paths' throughputs. Each tracer's workspace extends it with its own per-path state.
struct WavefrontBuffers {
    RayBatch rays, next, shadow;
    HitBatch hits;
    std::vector<uint8_t> occluded;
    std::vector<RGB> beta, shadow_value;
};

struct WavefrontStages {
    Stage intersect = Stage::Intersect;
    Stage shade = Stage::Shade;
    // Where the continuation rays are counted (nullptr: not counted).
    uint64_t RenderStats::*continuations = &RenderStats::secondary_rays;
    // false: the caller times the whole loop as one stage of its own (the gather rays).
    bool timed = true;
};

// Runs bounces depth, depth + 1, ... while rays are alive and depth < depth_end.
template <class Shade, class AfterShade>
void run_wavefront(const Intersector& accel, RayBatch& rays, RayBatch& next, HitBatch& hits,
                   uint32_t depth, uint32_t depth_end, RenderStats& stats, StageClock& clock,
                   Shade&& shade, AfterShade&& after_shade, const WavefrontStages& stages = {}) {
    for (; !rays.empty() && depth < depth_end; ++depth) {
        accel.intersect(rays, hits, stats.trace);
        if (stages.timed) stats.add(stages.intersect, rays.size(), clock);
        next.clear();
        shade(depth);
        if (stages.timed) stats.add(stages.shade, rays.size(), clock);
        after_shade(depth);
        if (stages.continuations) stats.*stages.continuations += next.size();
        std::swap(rays, next);
    }
}

// Without a step after shading.
template <class Shade>
void run_wavefront(const Intersector& accel, RayBatch& rays, RayBatch& next, HitBatch& hits,
                   uint32_t depth, RenderStats& stats, StageClock& clock, Shade&& shade,
                   const WavefrontStages& stages = {}) {
    run_wavefront(
        accel, rays, next, hits, depth, std::numeric_limits<uint32_t>::max(), stats, clock,
        std::forward<Shade>(shade), [](uint32_t) {}, stages);
}

}  // namespace foton
