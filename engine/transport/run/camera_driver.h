#pragma once
// The tile driver of the camera integrators: the image is cut into tiles, tiles run in
// parallel on oneTBB inside a task_arena of the requested size, and every tile's samples go
// to the integrator as one list (traced as a wavefront of ray batches). A pass gives every
// pixel `spp` samples, or, adaptive, as many as its error asks for; a time budget or a pass
// count repeats passes (pass_control.h). Tiles own their pixels, so the image is
// bit-identical for any thread count.
#include "engine/scene/scene.h"
#include "engine/transport/common/camera_integrator.h"
#include "render_options.h"
#include "render_settings.h"
#include "stage_graph.h"

namespace foton {

// A render of its own: the result's stats hold the graph of tile nodes.
RenderResult render_camera(const Scene& scene, const RenderSettings& settings,
                           const CameraIntegrator& integrator, const RenderOptions& options);
// The camera pass as the last nodes of `graph`, after the nodes `after` (which have run).
RenderResult render_camera(const Scene& scene, const RenderSettings& settings,
                           const CameraIntegrator& integrator, const RenderOptions& options,
                           StageGraph& graph, const std::vector<uint32_t>& after);

}  // namespace foton
