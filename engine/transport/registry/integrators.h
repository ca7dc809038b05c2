#pragma once
// The integrators foton knows, by name: the one table a new integrator is added to (with
// its folder and its line in engine/CMakeLists.txt). The renderer's `type` setting picks an
// entry; render() runs it. Everything that lists integrators reads this table: the command
// line's help, `foton serve`'s page, the pbrt importer, the golden images and the tests that
// run every integrator.
#include <optional>
#include <string>
#include <vector>

#include "engine/accel/intersector.h"
#include "engine/scene/scene.h"
#include "engine/transport/run/render_options.h"
#include "engine/transport/run/render_settings.h"

namespace foton {

struct IntegratorInfo {
    const char* name;
    std::vector<const char*> aliases;
    const char* summary;  // one line, for help texts
    uint32_t caps = 0;    // Capability bits (render_settings.h)
    // Reads the keys only this integrator takes into RenderSettings::own (after the shared
    // ones; keys nobody read are rejected after it); nullptr when it has none.
    void (*parse)(const ParamSet& params, RenderSettings& settings) = nullptr;
    RenderResult (*render)(const Scene& scene, const RenderSettings& settings,
                           const Intersector& accel, const RenderOptions& options) = nullptr;
    bool has(uint32_t cap) const { return (caps & cap) == cap; }
};

const std::vector<IntegratorInfo>& integrators();
// By name or alias; nullptr when there is none.
const IntegratorInfo* find_integrator(const std::string& name);
// "raytracer, path, ...": for error messages and help (`separator` between names).
std::string integrator_list(const char* separator = ", ");
// One line per integrator, "name (aliases): summary", for the command line's help.
std::string integrator_help();
// `type="a"`, `type="a" or "b"`, `type="a", "b" or "c"`: the integrators with every bit of
// `caps`, for error messages.
std::string integrators_with(uint32_t caps);

// What the chosen integrator cannot do with these settings: the setting's key and why, or
// nothing. render_settings() reports it at the key's file and line; render() refuses settings
// made by hand that break it.
struct SettingsProblem {
    const char* key;
    std::string message;
};
std::optional<SettingsProblem> capability_problem(const IntegratorInfo& info,
                                                  const RenderSettings& settings);

// The renderer's settings from a ParamSet (the scene's <renderer> with --set applied): every
// key typed and checked, unknown keys and integrator names rejected at their file and line.
RenderSettings render_settings(const ParamSet& params);
inline RenderSettings render_settings(const Scene& scene) {
    return render_settings(scene.renderer);
}

}  // namespace foton
