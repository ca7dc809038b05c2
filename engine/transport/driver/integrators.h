#pragma once
// The integrators foton knows, by name: the one table a new integrator is added to (with
// its folder and its line in engine/CMakeLists.txt). The renderer's `type` setting picks an
// entry; render() runs it.
#include <string>
#include <vector>

#include "engine/accel/intersector.h"
#include "engine/scene/scene.h"
#include "render_options.h"
#include "render_settings.h"

namespace foton {

struct IntegratorInfo {
    const char* name;
    std::vector<const char*> aliases;
    // Paths start at the camera, pixel by pixel: adaptive sampling applies.
    bool camera = true;
    // Takes indirect="irradiance_cache".
    bool irradiance_cache = false;
    RenderResult (*render)(const Scene& scene, const RenderSettings& settings,
                           const Intersector& accel, const RenderOptions& options) = nullptr;
};

const std::vector<IntegratorInfo>& integrators();
// By name or alias; nullptr when there is none.
const IntegratorInfo* find_integrator(const std::string& name);
// "raytracer, path, ...": for error messages.
std::string integrator_list();

// The renderer's settings from a ParamSet (the scene's <renderer> with --set applied): every
// key typed and checked, unknown keys and integrator names rejected at their file and line.
RenderSettings render_settings(const ParamSet& params);
inline RenderSettings render_settings(const Scene& scene) {
    return render_settings(scene.renderer);
}

}  // namespace foton
