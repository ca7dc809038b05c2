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
        std::string s = printable(file, 1000);
        if (line > 0) {
            s.push_back(':');
            s.append(std::to_string(line));
        }
        s.append(": ");
        s.append(printable(what, 2000));
        return s;
    }
    // A message quotes what the user wrote: control bytes are shown as \xNN (no terminal
    // escapes), and a huge value is cut, saying how much was left out.
    static std::string printable(const std::string& text, std::size_t max) {
        std::string out;
        const std::size_t n = text.size() < max ? text.size() : max;
        for (std::size_t i = 0; i < n; ++i) {
            const unsigned char c = static_cast<unsigned char>(text[i]);
            if (c < 0x20 || c == 0x7f) {
                static const char* hex = "0123456789abcdef";
                out += "\\x";
                out += hex[c >> 4];
                out += hex[c & 15];
            } else {
                out += char(c);
            }
        }
        if (text.size() > max)
            out += "... (" + std::to_string(text.size() - max) + " more characters)";
        return out;
    }
    std::string file_;
    int line_;
};

}  // namespace foton
