#pragma once
// Where camera subpaths start: their rays, and the light path each is joined to.
#include <cstdint>

#include "camera_workspace.h"
#include "vcm_context.h"

namespace foton {

// The camera rays of camera subpaths [first, first + count) into ws.rays (ray k for path
// k): film pixels first.. (row-major) sampled by the renderer's sampler, each joined to the
// light path of its pixel's place in the image; or, with c.primary, at the film position and
// lens point of path k's primary vector, joined to light path first + k. Sets ws.path.
void start_camera_rays(const VcmContext& c, uint32_t first, uint32_t count,
                       CameraSubpathWorkspace& ws);

}  // namespace foton
