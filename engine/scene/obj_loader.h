#pragma once
// Wavefront OBJ reader for triangle meshes. Our own small parser rather than a library
// because every problem must be reported with its line number (file:line: what), and the
// libraries available report index errors without one.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "mesh.h"

namespace foton {

struct ObjLoadResult {
    TriangleMesh mesh;                   // with uv when every face gave texture coordinates
    std::size_t degenerate_skipped = 0;  // zero-area or repeated-corner triangles
    bool has_normals = false;            // the file gave vertex normals (vn) for all faces
    // Materials: the mtllib files named (with their lines), the usemtl names in order of
    // first use, and each kept triangle's index into them (-1: before any usemtl).
    struct Library {
        std::string file;
        int line = 0;
    };
    std::vector<Library> libraries;
    std::vector<std::string> material_names;
    std::vector<int> material_lines;  // where each name was first used
    std::vector<int32_t> triangle_material;
};

// Reads `path`; polygons are fanned into triangles. Throws InputError on malformed lines,
// NaN/Inf coordinates, face indices out of range, or a file without faces.
ObjLoadResult load_obj(const std::string& path);
// Same, from text in memory (`name` is used in messages).
ObjLoadResult parse_obj(const std::string& text, const std::string& name);

}  // namespace foton
