#pragma once
// `foton render model.glb`: a model file (glTF, OBJ, PLY) made a scene of its own, with the
// file's materials (grey where it gives none), its lights or else a constant white sky, a
// 640 x 480 film, the
// path tracer, and a camera framing the model's bounds from the front, right and above
// (+z, +x, +y: glTF's and most OBJ files' y-up convention), its whole bounding sphere in view.
#include <string>

#include "scene.h"
#include "xml_loader.h"

namespace foton {

bool is_model_file(const std::string& path);
Scene model_scene(const std::string& path, const RendererOverrides& overrides = {});

}  // namespace foton
