#pragma once
// What tinygltf may read for foton, checked before the library reads it: JSON no deeper than
// a parser's stack takes, external files only under the model's own folder, images only of
// the size the texture limits allow. tinygltf parses recursively, follows a buffer's URI
// (percent-decoded, "../" included) wherever it points, and decodes an embedded image before
// anyone sees its size; each of those crashed or exhausted the process on a small hostile
// file (issue 34, defects 1, 3, 4).
#include <cstddef>
#include <string>
#include <string_view>

namespace tinygltf {
class TinyGLTF;
}

namespace foton {

// JSON nested deeper than this ([ and {) is refused: the parser recurses once per level.
inline constexpr std::size_t kMaxGltfJsonDepth = 256;

// The deepest nesting of [ and { in JSON text (strings skipped).
std::size_t json_nesting_depth(std::string_view json);
// A .glb's JSON chunk; empty when the header is malformed (the loader then says so).
std::string_view glb_json_chunk(std::string_view bytes);

// What the callbacks installed by guard_gltf_loader read: the model's folder (canonical).
struct GltfFileRoot {
    std::string folder;
};
// tinygltf reads external buffers and images only as regular files under root.folder (no
// "~" or environment expansion, no current-directory fallback outside it), and decodes only
// images whose header claims a size within the texture limits. `root` must outlive `loader`'s
// use.
void guard_gltf_loader(tinygltf::TinyGLTF& loader, GltfFileRoot& root);

}  // namespace foton
