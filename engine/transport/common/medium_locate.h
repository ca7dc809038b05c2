#pragma once
// Which medium a point is in, for paths that do not start at the camera (light paths,
// photons): found by walking the straight line from the camera, whose medium the scene gives,
// to the point, and changing medium at every boundary the line crosses (the rule camera rays
// follow: scene/medium.h). Other surfaces on the way are passed. Exact wherever the
// boundaries are closed, as the camera's own rays need them to be.
#include <cstdint>
#include <string>
#include <vector>

#include "engine/accel/intersector.h"
#include "engine/core/math.h"
#include "engine/scene/light_set.h"
#include "engine/scene/scene.h"

namespace foton {

int32_t locate_medium(const Scene& scene, const Intersector& accel, const Vec3& p);

// Each emitter's medium: where a fixed emitted ray of it starts (a light is taken to lie in
// one medium, as photons and light paths need it to).
std::vector<int32_t> light_media(const Scene& scene, const Intersector& accel,
                                 const LightSet& lights);

// Paths that start at lights miss the light media emit: an integrator built on them refuses
// an emitting medium at its line, "medium 'NAME' emits, and <why>".
void refuse_emitting_media(const Scene& scene, const std::string& why);

}  // namespace foton
