#pragma once
// Rendering entry point: the settings' integrator (a name in integrators.h's table) renders
// the scene. Camera integrators (raytracer, path, distributed, photon) go through the tile
// driver (camera_driver.h), the light tracer through its own pass loop, SPPM/PPM through
// their passes, and photon mapping and the irradiance cache through their stage graphs. All
// random numbers are counter-based and work is merged in a fixed order, so the image is
// bit-identical for any thread count.
#include "engine/accel/intersector.h"
#include "engine/scene/scene.h"
#include "engine/transport/run/render_options.h"
#include "engine/transport/run/render_settings.h"
#include "integrators.h"

namespace foton {

RenderResult render(const Scene& scene, const RenderSettings& settings, const Intersector& accel,
                    const RenderOptions& options);
// With the scene's own settings (its <renderer>, --set applied).
RenderResult render(const Scene& scene, const Intersector& accel, const RenderOptions& options);
// The integrator as the tools name it: its name, and "spectral" after volpath's when it
// renders spectrally.
std::string integrator_label(const RenderSettings& settings);

}  // namespace foton
