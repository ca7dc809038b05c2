#pragma once
// The scenes `foton serve`'s page may open: every .xml and .pbrt file under the given folders,
// subfolders included, named "<root>/<path under it>". Two roots with the same folder name get
// longer prefixes (their parent folders) until the names differ. A file whose real path leaves
// its root (a symlink out of it) is not listed, so the page can open nothing outside the
// folders; the server opens scenes only by these names, never by a path the page sends.
#include <map>
#include <string>
#include <vector>

namespace foton::app {

// name -> path. Throws InputError for a folder that is not one.
std::map<std::string, std::string> list_scenes(const std::vector<std::string>& roots);
// The same for files of other extensions (".exr": the references the page may compare with).
std::map<std::string, std::string> list_files(const std::vector<std::string>& roots,
                                              const std::vector<std::string>& extensions);

}  // namespace foton::app
