#pragma once
// Files a command will write: checked before any work, so that a render never ends in an
// error about where its result was to go.
#include <string>
#include <vector>

namespace foton::app {

// `path`'s directory must exist (or be creatable) and be writable, and `path` must not be a
// directory, nor `input` (the scene) itself. Throws InputError naming `what` (the flag).
void check_writable(const std::string& path, const char* what, const std::string& input = "");

// The files a command reads and writes: every output must be writable (check_writable) and a
// different file from every input and every other output, so that `-o a.exr --stats-json
// a.exr`, an output over the --reference, or `compare a b --diff a` fail before any work
// instead of overwriting what they read or wrote.
class FilePlan {
  public:
    // `what` names the input in messages ("the scene file", "--reference").
    void input(const std::string& path, const std::string& what);
    // `what` is the flag that names the output.
    void output(const std::string& path, const std::string& what);

  private:
    struct Entry {
        std::string key;  // the absolute, normalised path
        std::string what;
    };
    static std::string key_of(const std::string& path);
    std::vector<Entry> inputs_, outputs_;
};

}  // namespace foton::app
