#pragma once
// Ambient occlusion (`type="ao"`): the fraction of the hemisphere above the first visible
// surface that no geometry closes within `ao_distance` (0: any distance), estimated with
// `ao_samples` cosine-weighted rays, so a pixel is (1 / pi) times the cosine-weighted visible
// solid angle, as pbrt-v4's "ambientocclusion" integrator computes it; camera rays that miss
// are 0. A research aid for checking geometry and accelerators, and the example of what a new
// integrator touches: this folder, its row in transport/registry/integrators.cpp and its source
// line in engine/CMakeLists.txt.
#include "engine/accel/intersector.h"
#include "engine/core/params.h"
#include "engine/transport/run/render_options.h"
#include "engine/transport/run/render_settings.h"

namespace foton {

struct AoSettings {
    uint32_t samples = 16;
    float distance = 0.f;  // 0: unbounded
};

// The row's parse: ao_samples and ao_distance into RenderSettings::own.
void parse_ao(const ParamSet& params, RenderSettings& settings);
// The row's render: the tile driver over the AO integrator.
RenderResult render_ao(const Scene& scene, const RenderSettings& settings, const Intersector& accel,
                       const RenderOptions& options);

}  // namespace foton
