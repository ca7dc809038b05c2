#pragma once
// Writing a result file so that it is whole or absent: written to a hidden temporary file
// beside it, every write checked, flushed to the disk (fsync), then renamed over the target.
// A full disk, a file-size limit or an I/O error is an InputError naming the file, never a
// 0-byte image with "wrote" printed; an interrupt removes the temporary file.
#include <functional>
#include <string>

namespace foton {

// Runs `write(tmp)`, which writes the whole file at tmp (and throws if it cannot), then syncs
// tmp to the disk and renames it to `path`; on any failure tmp is removed and the error
// propagates (write errors as InputError(path, 0, "cannot write: <reason>")).
void write_atomically(const std::string& path,
                      const std::function<void(const std::string&)>& write);
// `bytes` as the whole file at `path`, through write_atomically.
void write_file_bytes(const std::string& path, const std::string& bytes);
// Removes the temporary file being written, if any: async-signal-safe, for an interrupt
// handler that is about to end the process.
void remove_pending_temp_file() noexcept;

}  // namespace foton
