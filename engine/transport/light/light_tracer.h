#pragma once
// Light tracing (the photon-mapping thesis, chapter 4.3): paths start at the lights, chosen
// by power, and every vertex with a non-delta BSDF (and the emitting point itself) is joined
// to the pinhole by a shadow ray; what arrives is splatted onto the pixel it projects to.
// The transport is adjoint (importance): dielectric refraction is not scaled by eta^2 and
// shading normals get Veach's correction.
//
// Determinism: paths are numbered; a chunk of consecutive paths is traced as one wavefront
// and returns its splats in path order; the driver adds the chunks' splats to the film in
// chunk order, so the sum is the same whatever thread traced which chunk.
#include <cstdint>
#include <vector>

#include "engine/accel/intersector.h"
#include "engine/core/ray_batch.h"
#include "engine/core/stats.h"
#include "engine/film/pixel_sums.h"
#include "engine/scene/light_set.h"
#include "engine/transport/common/wavefront.h"
#include "engine/transport/run/render_context.h"

namespace foton {

struct LightTracerWorkspace : WavefrontBuffers {
    std::vector<uint32_t> shadow_pixel;  // the film pixel each shadow ray's splat lands on
};

class LightTracer {
  public:
    explicit LightTracer(const RenderContext& ctx) : ctx_(ctx) {}
    // Traces paths [first, first + count) and appends their (unoccluded) splats. A splat's
    // value is one path's contribution: the pixel estimate is the splat sum over the number
    // of paths traced.
    void trace(uint64_t first, uint32_t count, LightTracerWorkspace& ws, std::vector<Splat>& splats,
               RenderStats& stats) const;

  private:
    float rand(uint64_t path, uint32_t dim) const;

    const RenderContext ctx_;
};

}  // namespace foton
