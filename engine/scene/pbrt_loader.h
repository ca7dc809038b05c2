#pragma once
// pbrt-v4 scene files (`foton render scene.pbrt`): the directives, shapes, materials and
// lights that foton can render (scenes/README.md lists them), imported into a foton Scene.
// What foton leaves out is a warning at its file and line (Scene::warnings); what would
// make the image wrong is an InputError, `file:line: what`.
#include <string>

#include "scene.h"
#include "xml_loader.h"

namespace foton {

// A pbrt-v4 scene from text in memory (load_scene reads .pbrt files into it); Include paths
// and meshes resolve against `base_dir`.
Scene parse_pbrt_scene(const std::string& text, const std::string& name,
                       const std::string& base_dir, const RendererOverrides& overrides = {});

}  // namespace foton
