#pragma once
// The camera half of an iteration: one camera subpath per pixel, traced as a wavefront. At
// each vertex it gathers every strategy that ends there: the light found by the ray (s = 0),
// a light sample (s = 1), connections to the vertices of the pixel's own light path (s >= 2)
// and merges with the vertices of all light paths within the radius, each with its MIS
// weight (vcm_mis.h). The connections' shadow rays of a bounce are tested as one batch. At
// vertices on the materials the diffuse kernel takes, the BSDF values and densities the
// connections and merges need are queued and evaluated as one batch of lobe pairs
// (common/lobe_pairs.h) after the bounce's hits.
#include <cstdint>
#include <vector>

#include "camera_workspace.h"
#include "engine/core/stats.h"
#include "vcm_context.h"

namespace foton {

// Traces the camera subpaths of film pixels [first, first + count) (row-major) and writes
// each pixel's estimate of this iteration to `radiance` (count entries), and with
// c.layers enabled and `layers` given, what each strategy added (c.layers.count() entries
// per pixel) to `layers`. Through media when the scene has them (subpath_media.h).
void trace_camera_subpaths(const VcmContext& c, const LightPathStore& store, uint32_t first,
                           uint32_t count, CameraSubpathWorkspace& ws, std::vector<RGB>& radiance,
                           std::vector<RGB>* layers, RenderStats& stats);

}  // namespace foton
