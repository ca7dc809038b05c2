#pragma once
// The command line's flags that change the scene, shared by `foton render` and `foton scale`:
// --set key=value overrides of <renderer>, --accel, and the settings as a run used them.
#include <string>
#include <vector>

#include "engine/scene/scene.h"
#include "engine/scene/xml_loader.h"

namespace foton::app {

// --set's key=value pairs, checked (InputError for a pair without a key or an '=').
RendererOverrides parse_set_flags(const std::vector<std::string>& set);
// --accel NAME, when given, replaces the scene's <aggregate> (InputError for an unknown name).
void apply_accel_flag(const std::string& name, Scene& scene);
// Every renderer setting as the run used it, the file's and the flags' alike: "k=v k=v".
std::string settings_text(const Scene& scene);

}  // namespace foton::app
