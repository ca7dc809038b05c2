// Scene files by format: read once, with the same size limit and messages, then parsed by
// the loader their extension chooses.
#include <cctype>
#include <filesystem>

#include "engine/core/error.h"

#include "engine/core/input_file.h"
#include "model_scene.h"
#include "pbrt_loader.h"
#include "xml_loader.h"

namespace foton {

Scene load_scene(const std::string& path, const RendererOverrides& overrides) {
    // A model is not a scene: it has no camera, lights or film. Said before reading, instead
    // of the XML parser's "malformed" at its first binary byte.
    const std::string ext = lower_extension(path);
    if (is_model_file(path)) return model_scene(path, overrides);
    if (ext == ".mtl")
        throw InputError(path, 0,
                         "an OBJ material library, not a scene: render the .obj that names it");
    for (const char* image : {".exr", ".png", ".hdr", ".jpg", ".jpeg", ".bmp", ".tga", ".pfm"})
        if (ext == image)
            throw InputError(path, 0,
                             "an image, not a scene (foton reads XML and pbrt-v4 scenes; "
                             "`foton compare` reads images)");
    const std::string text = read_input_file(path, kMaxSceneFileBytes, "scene file");
    const std::string dir = std::filesystem::path(path).parent_path().string();
    const std::string base = dir.empty() ? "." : dir;
    if (std::filesystem::path(path).extension() == ".pbrt")
        return parse_pbrt_scene(text, path, base, overrides);
    return parse_scene(text, path, base, overrides);
}

}  // namespace foton
