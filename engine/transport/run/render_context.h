#pragma once
// What every integrator of one render reads: the scene, its settings, the accelerator, the
// lights and the render's seed. One struct instead of the same five references in every
// integrator, evaluator and tracer; it holds references, so it lives no longer than the
// render function that made it.
#include <cstdint>

#include "engine/accel/intersector.h"
#include "engine/scene/light_set.h"
#include "engine/scene/scene.h"
#include "render_settings.h"

namespace foton {

struct RenderContext {
    const Scene& scene;
    const RenderSettings& settings;
    const Intersector& accel;
    const LightSet& lights;
    uint64_t seed = 0;
};

}  // namespace foton
