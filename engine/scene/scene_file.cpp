// Scene files by format: read once, with the same size limit and messages, then parsed by
// the loader their extension chooses.
#include <filesystem>

#include "engine/core/input_file.h"
#include "pbrt_loader.h"
#include "xml_loader.h"

namespace foton {

Scene load_scene(const std::string& path, const RendererOverrides& overrides) {
    const std::string text = read_input_file(path, kMaxSceneFileBytes, "scene file");
    const std::string dir = std::filesystem::path(path).parent_path().string();
    const std::string base = dir.empty() ? "." : dir;
    if (std::filesystem::path(path).extension() == ".pbrt")
        return parse_pbrt_scene(text, path, base, overrides);
    return parse_scene(text, path, base, overrides);
}

}  // namespace foton
