#include "output_paths.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include <filesystem>

#include "engine/core/error.h"

namespace foton::app {

namespace fs = std::filesystem;

void check_writable(const std::string& path, const char* what, const std::string& input) {
    const fs::path p(path);
    std::error_code ec;
    if (fs::is_directory(p, ec)) throw InputError(what, 0, "'" + path + "' is a directory");
    if (!input.empty() && fs::exists(p, ec) && fs::equivalent(p, input, ec))
        throw InputError(what, 0, "'" + path + "' is the scene file itself");
    const fs::path dir = p.parent_path().empty() ? fs::path(".") : p.parent_path();
    fs::create_directories(dir, ec);
    if (ec || access(dir.c_str(), W_OK) != 0)
        throw InputError(what, 0,
                         "cannot write '" + path + "' (" +
                             (ec ? ec.message() : std::string("directory not writable")) + ")");
    // access() says yes for root almost everywhere (/proc, a read-only mount answers only on
    // writing): a probe file is created and removed, so the render does not end in an error.
    const fs::path probe = dir / (".foton-probe-" + std::to_string(getpid()));
    const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
    if (fd < 0)
        throw InputError(what, 0,
                         "cannot write '" + path + "' (" + std::string(std::strerror(errno)) + ")");
    ::close(fd);
    ::unlink(probe.c_str());
}

std::string FilePlan::key_of(const std::string& path) {
    std::error_code ec;
    const fs::path p = fs::weakly_canonical(fs::absolute(path, ec), ec);
    return (ec ? fs::absolute(path).lexically_normal() : p).string();
}

void FilePlan::input(const std::string& path, const std::string& what) {
    if (!path.empty()) inputs_.push_back({key_of(path), what});
}

void FilePlan::output(const std::string& path, const std::string& what) {
    check_writable(path, what.c_str());
    const std::string key = key_of(path);
    for (const Entry& e : inputs_)
        if (e.key == key) throw InputError(what, 0, "'" + path + "' is " + e.what + " itself");
    for (const Entry& e : outputs_)
        if (e.key == key) throw InputError(what, 0, "'" + path + "' is also written by " + e.what);
    outputs_.push_back({key, what});
}

}  // namespace foton::app
