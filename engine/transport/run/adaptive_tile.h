#pragma once
// Adaptive sampling of one camera tile (the thesis' section 6.2): a pilot of `pilot` samples
// per pixel, then either rounds that double the samples of every pixel whose relative standard
// error is above the threshold (biased: the stopping rule sees the samples it averages), or,
// unbiased (Kirk & Arvo), one fresh batch sized from the pilot's variance with the pilot
// discarded.
#include <vector>

#include "camera_tile.h"
#include "engine/scene/scene.h"
#include "engine/transport/common/camera_integrator.h"
#include "render_settings.h"

namespace foton {

// The tile's sums per pixel go to `out_sums` (with `ws.part_count` components each); `jobs`
// and `out` are scratch.
void adaptive_tile(const Scene& scene, const AdaptiveSettings& ad, SamplerKind sampler,
                   uint64_t seed, const CameraIntegrator& integrator, const Tile& t,
                   IntegratorWorkspace& ws, RenderStats& st, std::vector<SampleJob>& jobs,
                   std::vector<RGB>& out, TileSums& out_sums);

}  // namespace foton
