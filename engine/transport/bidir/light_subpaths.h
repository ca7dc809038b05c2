#pragma once
// The light half of an iteration: light subpaths traced as a wavefront, their non-delta
// vertices stored with their MIS sums (light_vertices.h), and each vertex joined to the
// camera (the t = 1 strategy, light tracing) when connections are on. Paths are numbered
// within the iteration; a chunk of consecutive paths returns its vertices path by path and
// its splats in path order, so the iteration's result does not depend on the threads.
#include <cstdint>
#include <vector>

#include "engine/core/ray_batch.h"
#include "engine/core/stats.h"
#include "engine/transport/light/light_tracer.h"
#include "light_vertices.h"
#include "subpath_media.h"
#include "vcm_context.h"

namespace foton {

struct LightSubpathWorkspace : LightTracerWorkspace {
    std::vector<SubpathMis> mis;
    std::vector<uint16_t> length;
    std::vector<float> emit_pdf, pick;  // the emission's density, the light's selection
    std::vector<uint32_t> light;
    std::vector<Vec3> origin, origin_n;  // the emitted point and its normal
    std::vector<uint8_t> infinite;
    LightVertices local;  // the chunk's vertices in wavefront order
    SubpathMedia media;
    JoinRays joins;  // the joins to the camera: slot = their film point in shadow_at
};

// Traces light paths [first, first + count) of the iteration; appends their vertices, path
// by path, to `out` and their camera splats to `splats` (values already divided by N); with
// c.layers enabled and `splat_layers` given, each splat's strategy layer to it (with
// c.primary, its path's index instead). Through media when the scene has them
// (subpath_media.h).
void trace_light_subpaths(const VcmContext& c, uint32_t first, uint32_t count,
                          LightSubpathWorkspace& ws, LightVertices& out, std::vector<Splat>& splats,
                          std::vector<uint32_t>* splat_layers, RenderStats& stats);

}  // namespace foton
