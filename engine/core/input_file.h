#pragma once
// Reading an input file (a scene, a mesh) whole, as bad input when it is not a readable
// regular file of sensible size: a FIFO, a device, a directory, a symlink loop or an
// over-long name gets a message naming the file, never a hang or an internal error.
#include <cstdint>
#include <string>
#include <vector>

namespace foton {

constexpr uint64_t kMaxSceneFileBytes = uint64_t(64) << 20;  // 64 MiB of XML
constexpr uint64_t kMaxMeshFileBytes = uint64_t(4) << 30;    // 4 GiB of OBJ

// The file's contents; InputError(path, 0, "cannot read <what>: reason") otherwise.
std::string read_input_file(const std::string& path, uint64_t max_bytes, const char* what);
// Why `path` cannot be read as an input file ("" when it can).
std::string input_file_problem(const std::string& path, uint64_t max_bytes);

// The folders every input file must lie in, symlinks resolved; none (the default) lets every
// path be read. `foton serve` confines the scenes it renders to its scene folders and its
// --allow-read ones, so a request cannot make it open, or quote in an error it publishes, any
// other file (a mesh's `mtllib /etc/passwd`). Set once, before threads read inputs.
void confine_inputs(const std::vector<std::string>& folders);
// The folders set by confine_inputs (canonical), for messages.
const std::vector<std::string>& input_confinement();

// The file name's extension, lower case, with its dot (".obj"); empty when there is none.
std::string lower_extension(const std::string& path);

}  // namespace foton
