#pragma once
// The XML scene format (see scenes/README.md): a superset of the first thesis' appendix A.
// Every problem is reported as InputError `file:line: what` and nothing is half-loaded.
#include <string>

#include "scene.h"

namespace foton {

Scene load_scene(const std::string& path);
// Same, from XML text in memory; relative mesh paths resolve against `base_dir`.
Scene parse_scene(const std::string& xml, const std::string& name, const std::string& base_dir);

}  // namespace foton
