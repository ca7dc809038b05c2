#pragma once
// Files a command will write: checked before any work, so that a render never ends in an
// error about where its result was to go.
#include <string>

namespace foton::app {

// `path`'s directory must exist (or be creatable) and be writable, and `path` must not be a
// directory, nor `input` (the scene) itself. Throws InputError naming `what` (the flag).
void check_writable(const std::string& path, const char* what, const std::string& input = "");

}  // namespace foton::app
