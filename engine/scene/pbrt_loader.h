#pragma once
// pbrt-v4 scene files (`foton render scene.pbrt`): the directives, shapes, materials and
// lights that foton can render (scenes/README.md lists them), imported into a foton Scene.
// What foton leaves out is a warning at its file and line (Scene::warnings); what would
// make the image wrong is an InputError, `file:line: what`.
#include <string>

#include "scene.h"
#include "xml_loader.h"

namespace foton {

Scene load_pbrt_scene(const std::string& path, const RendererOverrides& overrides = {});
// Same, from text in memory; Include paths and meshes resolve against `base_dir`.
Scene parse_pbrt_scene(const std::string& text, const std::string& name,
                       const std::string& base_dir, const RendererOverrides& overrides = {});

}  // namespace foton
