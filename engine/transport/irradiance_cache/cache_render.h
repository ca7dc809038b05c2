#pragma once
// Rendering through a camera integrator with an irradiance cache: one cache per level,
// filled in hierarchical passes (cache_fill.h), then read, frozen, by the image pass.
#include <functional>

#include "cache_evaluator.h"
#include "engine/accel/intersector.h"
#include "engine/scene/light_set.h"
#include "engine/transport/common/camera_integrator.h"
#include "engine/transport/common/radiance_along_rays.h"
#include "engine/transport/run/render_options.h"
#include "engine/transport/run/render_settings.h"
#include "engine/transport/run/stage_graph.h"

namespace foton {

// The secondary evaluation the settings ask for; Auto and "photon" depend on whether a
// photon map is there to read.
CacheSecondary cache_secondary(const CacheSettings& settings, bool photon_map);

// The cache fill and the camera pass as the last nodes of `graph`, after `after`. `attach`
// hands the evaluator to the integrator (and nullptr at the end); `photons` (null without a
// photon map) and `onwards` serve the photon and path secondary modes.
RenderResult render_with_cache(const Scene& scene, const RenderSettings& settings,
                               const Intersector& accel, const LightSet& lights,
                               const CameraIntegrator& integrator,
                               const std::function<void(const CacheEvaluator*)>& attach,
                               CacheEvaluator::PhotonRadiance photons,
                               const RadianceAlongRays& onwards, const RenderOptions& options,
                               StageGraph& graph, const std::vector<uint32_t>& after);

}  // namespace foton
