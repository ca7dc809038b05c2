#pragma once
// Compressed input files: gzip (.gz, through zlib) and xz (.xz, through liblzma), as public
// scene collections ship their meshes (pbrt-v4-scenes' .ply.gz). Corrupt, truncated or
// oversized data is bad input naming the file, never a crash or a partial mesh.
#include <cstdint>
#include <string>

namespace foton {

// Whether `path` names a compressed file foton reads (.gz or .xz, any case).
bool is_compressed_input(const std::string& path);

// `data`, the whole content of the compressed file `path`, decompressed; at most max_bytes
// of output. InputError(path, 0, ...) when the data is not of its format, is corrupt or
// truncated, or decompresses to more than max_bytes.
std::string decompress_input(const std::string& data, const std::string& path, uint64_t max_bytes);

// read_input_file, decompressed when `path` is compressed (both limited to max_bytes).
std::string read_input_file_decompressed(const std::string& path, uint64_t max_bytes,
                                         const char* what);

}  // namespace foton
