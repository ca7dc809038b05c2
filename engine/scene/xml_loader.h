#pragma once
// The XML scene format (see scenes/README.md): a superset of the first thesis' appendix A.
// Every problem is reported as InputError `file:line: what` and nothing is half-loaded.
#include <string>
#include <utility>
#include <vector>

#include "scene.h"

namespace foton {

// `key=value` settings that replace (or add) attributes of <renderer> before it is read:
// the command line's --set. They are checked like the file's own attributes.
using RendererOverrides = std::vector<std::pair<std::string, std::string>>;

// A scene file of any supported format, chosen by its extension: .pbrt is pbrt-v4's, any
// other is foton's XML.
Scene load_scene(const std::string& path, const RendererOverrides& overrides = {});
// Same, from XML text in memory; relative mesh paths resolve against `base_dir`.
Scene parse_scene(const std::string& xml, const std::string& name, const std::string& base_dir,
                  const RendererOverrides& overrides = {});

}  // namespace foton
