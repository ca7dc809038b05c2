#include "scene_flags.h"

#include "engine/core/error.h"

namespace foton::app {

RendererOverrides parse_set_flags(const std::vector<std::string>& set) {
    RendererOverrides overrides;
    for (const std::string& kv : set) {
        const auto eq = kv.find('=');
        if (eq == std::string::npos || eq == 0)
            throw InputError("--set", 0, "expected key=value, got '" + kv + "'");
        overrides.emplace_back(kv.substr(0, eq), kv.substr(eq + 1));
    }
    return overrides;
}

void apply_accel_flag(const std::string& name, Scene& scene) {
    if (!name.empty() && !parse_accel(name, scene.accel))
        throw InputError("--accel", 0,
                         "unknown accelerator '" + name +
                             "' (brute, brute-simd, grid, bvh, embree, octree, kdtree)");
}

std::string settings_text(const Scene& scene) {
    std::string text;
    for (const std::string& key : scene.renderer.read_keys())
        if (scene.renderer.has(key))
            text += (text.empty() ? "" : " ") + key + "=" + scene.renderer.text(key);
    return text;
}

}  // namespace foton::app
