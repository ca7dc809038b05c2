// Scene files by format: the extension chooses the loader.
#include <filesystem>

#include "pbrt_loader.h"
#include "xml_loader.h"

namespace foton {

Scene load_scene(const std::string& path, const RendererOverrides& overrides) {
    if (std::filesystem::path(path).extension() == ".pbrt") return load_pbrt_scene(path, overrides);
    return load_xml_scene(path, overrides);
}

}  // namespace foton
