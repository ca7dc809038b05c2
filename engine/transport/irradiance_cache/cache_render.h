#pragma once
// Rendering through a camera integrator with an irradiance cache: one cache per level,
// filled in hierarchical passes (cache_fill.h), then read, frozen, by the image pass.
#include <functional>

#include "cache_evaluator.h"
#include "engine/accel/intersector.h"
#include "engine/scene/light_set.h"
#include "engine/transport/common/camera_integrator.h"
#include "engine/transport/common/radiance_along_rays.h"
#include "engine/transport/driver/render_options.h"
#include "engine/transport/driver/stage_graph.h"

namespace foton {

// The secondary evaluation the scene asks for, checked against the renderer.
CacheSecondary cache_secondary(const Scene& scene);

// `attach` hands the evaluator to the integrator (and nullptr at the end); `photons` and
// `onwards` serve the photon and path secondary modes.
RenderResult render_with_cache(const Scene& scene, const Intersector& accel, const LightSet& lights,
                               const CameraIntegrator& integrator,
                               const std::function<void(const CacheEvaluator*)>& attach,
                               CacheEvaluator::PhotonRadiance photons,
                               const RadianceAlongRays& onwards, const RenderOptions& options);
// The same as the last nodes of `graph` (cache-fill, then the camera's), after `after`.
RenderResult render_with_cache(const Scene& scene, const Intersector& accel, const LightSet& lights,
                               const CameraIntegrator& integrator,
                               const std::function<void(const CacheEvaluator*)>& attach,
                               CacheEvaluator::PhotonRadiance photons,
                               const RadianceAlongRays& onwards, const RenderOptions& options,
                               StageGraph& graph, const std::vector<uint32_t>& after);

}  // namespace foton
