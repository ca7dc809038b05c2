#pragma once
// Errors in what the user gave us (scene, mesh, flags): reported as `file:line: problem`,
// exit code 2. Anything else that goes wrong is an internal error, exit code 1.
#include <stdexcept>
#include <string>

namespace foton {

inline constexpr int kExitBadInput = 2;
inline constexpr int kExitInternal = 1;

class InputError : public std::runtime_error {
  public:
    InputError(std::string file, int line, const std::string& what)
        : std::runtime_error(format(file, line, what)), file_(std::move(file)), line_(line) {}
    const std::string& file() const { return file_; }
    int line() const { return line_; }

  private:
    static std::string format(const std::string& file, int line, const std::string& what) {
        std::string s = file;
        if (line > 0) {
            s.push_back(':');
            s.append(std::to_string(line));
        }
        s.append(": ");
        s.append(what);
        return s;
    }
    std::string file_;
    int line_;
};

}  // namespace foton
