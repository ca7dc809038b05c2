#pragma once
// The light tracer's pass loop: a pass traces width x height x spp light paths in fixed
// chunks of 4096 on all threads; the chunks' splats are added to the film in chunk order, so
// the image is bit-identical for any thread count.
#include "engine/accel/intersector.h"
#include "engine/scene/scene.h"
#include "engine/transport/run/render_options.h"
#include "engine/transport/run/render_settings.h"

namespace foton {

RenderResult render_light(const Scene& scene, const RenderSettings& settings,
                          const Intersector& accel, const RenderOptions& options);

}  // namespace foton
