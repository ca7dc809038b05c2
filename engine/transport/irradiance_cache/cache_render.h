#pragma once
// Rendering through a camera integrator with an irradiance cache: one cache per level,
// filled in hierarchical passes (cache_fill.h), then read, frozen, by the image pass.
#include <functional>
#include <memory>

#include "cache_evaluator.h"
#include "engine/accel/intersector.h"
#include "engine/scene/light_set.h"
#include "engine/transport/common/camera_integrator.h"
#include "engine/transport/common/radiance_along_rays.h"
#include "engine/transport/run/render_context.h"
#include "engine/transport/run/render_options.h"
#include "engine/transport/run/stage_graph.h"

namespace foton {

// The secondary evaluation the settings ask for; Auto and "photon" depend on whether a
// photon map is there to read, "path" on a path tracer to trace on (`onwards`).
CacheSecondary cache_secondary(const CacheSettings& settings, bool photon_map, bool onwards);

// Who traces on from a record's hemisphere rays for secondary="path": made per render.
using PathOnwards = std::function<std::unique_ptr<RadianceAlongRays>(const RenderContext&)>;

// What the cache needs from the family that reads it, and nothing else.
struct CacheClient {
    // The camera integrator reading `cache` at its diffuse points. It fills the cache too
    // (hierarchically, reading the records made so far), then renders the image.
    std::function<std::unique_ptr<CameraIntegrator>(const CacheEvaluator& cache)> camera;
    // The radiance a record ray's hit sends back, from a photon map (secondary="photon");
    // empty without one.
    CacheEvaluator::PhotonRadiance photons;
    // Path tracing onwards (secondary="path"); null when the family has none to offer.
    const RadianceAlongRays* onwards = nullptr;
};

// The cache fill and the camera pass as the last nodes of `graph`, after `after`.
RenderResult render_with_cache(const RenderContext& ctx, const CacheClient& client,
                               const RenderOptions& options, StageGraph& graph,
                               const std::vector<uint32_t>& after);

}  // namespace foton
