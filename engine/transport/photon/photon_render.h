#pragma once
// Two-pass photon mapping as one job graph: the global and caustic passes (emit, trace and
// store, parallel inside) run side by side, each feeds the balancing of its kd-tree, the
// global tree feeds the precomputed irradiance, and all of it feeds the camera pass.
#include "engine/accel/intersector.h"
#include "engine/scene/scene.h"
#include "engine/transport/irradiance_cache/cache_render.h"
#include "engine/transport/run/render_options.h"
#include "engine/transport/run/render_settings.h"

namespace foton {

// With indirect="irradiance_cache" and cache_secondary="path", the cache's records trace on
// with `path_onwards` (the registry passes the path family's, so this family does not
// depend on it); without it that setting is refused.
RenderResult render_photon(const Scene& scene, const RenderSettings& settings,
                           const Intersector& accel, const RenderOptions& options,
                           const PathOnwards& path_onwards);

}  // namespace foton
