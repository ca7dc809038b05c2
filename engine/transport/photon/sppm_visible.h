#pragma once
// SPPM's camera pass: one camera sample per pixel, followed through specular chains to its
// visible point. A row of pixels is traced as batches (its rays at each depth, then its
// shadow rays), so the accelerator's stream kernels serve this pass as they serve
// the path tracer's; every pixel gets exactly what a ray-by-ray walk would give it.
#include <cstdint>
#include <vector>

#include "engine/accel/intersector.h"
#include "engine/core/ray_batch.h"
#include "engine/core/warp.h"
#include "engine/scene/light_set.h"
#include "engine/transport/run/render_context.h"

namespace foton {

struct SppmPixel {
    // The visible point of the current pass.
    bool valid = false;
    Vec3 p, ng;
    warp::Frame frame;
    Vec3 wo;  // local
    bool front = true;
    uint32_t material = 0;
    // Where the material's textures read themselves there (uv, footprint, vertex colour).
    TexPoint tex{Point2{0.f, 0.f}};
    RGB beta;
    RGB pass_direct;  // the current pass's direct light (emission and one NEE sample)
    // Progressive statistics.
    RGB direct;  // summed over passes
    float radius = 0.f;
    double n = 0.0;
    RGB tau;
};

// A thread's buffers for trace_row, kept across rows to avoid reallocating.
struct VisibleRowWork {
    RayBatch rays, next, shadow;
    HitBatch hits;
    std::vector<uint8_t> occluded;
    std::vector<RGB> beta;        // per pixel of the row: the path's throughput so far
    std::vector<RGB> shadow_add;  // per shadow ray: what it adds to its pixel when unblocked
};

class VisiblePoints {
  public:
    explicit VisiblePoints(const RenderContext& ctx) : ctx_(ctx) {}

    // The visible points of image row y (row[x] is pixel x of it) along the camera paths of
    // pass `camera_pass`, with the light samples of pass `light_pass` (PPM keeps the first
    // pass's points, camera_pass 0, and samples their direct light anew every pass); emission
    // found on the way and one NEE sample at each visible point go to `pass_direct`.
    void trace_row(uint64_t camera_pass, uint64_t light_pass, uint32_t y, SppmPixel* row,
                   VisibleRowWork& work, RenderStats& stats) const;

  private:
    float rand(uint64_t pass, uint64_t pixel, uint32_t dim) const;
    // One hit of pixel x's path: continues it in `work.next`, or ends it at its visible point
    // (queueing its shadow ray) or where nothing more can be found.
    void shade(uint64_t camera_pass, uint64_t light_pass, uint32_t y, uint32_t depth, std::size_t r,
               SppmPixel* row, VisibleRowWork& work, RenderStats& stats) const;

    const RenderContext ctx_;
};

}  // namespace foton
