#pragma once
// Rendering entry point: picks the scene's integrator family and runs it. Camera integrators
// (raytracer, path, distributed) go through the tile driver (camera_driver.h), the light
// tracer through its own pass loop (light/light_render.h), photon mapping through its job
// graph (photon/photon_render.h), SPPM/PPM through their passes (photon/sppm.h), and any of
// them with an irradiance cache through the cache's fill (irradiance_cache/cache_render.h).
// All random numbers are counter-based and work is merged in a fixed order, so the image is
// bit-identical for any thread count.
#include "engine/accel/intersector.h"
#include "engine/scene/scene.h"
#include "render_options.h"

namespace foton {

// Renders with the scene's integrator and settings (scene.render).
RenderResult render(const Scene& scene, const Intersector& accel, const RenderOptions& options);

}  // namespace foton
