#pragma once
// Stanford PLY meshes, ASCII and binary (either byte order): vertex positions, normals and
// texture coordinates, faces of any size fanned into triangles. Our own reader: Debian has
// no PLY library but Assimp, whose loaders report no line or byte offset and are not ours
// to fuzz; the format fits on a page. Every problem is an InputError naming the file and
// the header line, data line (ASCII) or byte offset (binary).
#include <string>

#include "mesh.h"

namespace foton {

TriangleMesh load_ply(const std::string& path);
// Same, from the file's bytes in memory (`name` is used in messages).
TriangleMesh parse_ply(const std::string& bytes, const std::string& name);

}  // namespace foton
