#include "file_write.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <filesystem>

#include "engine/core/error.h"

namespace foton {

namespace {

// The temporary file being written, for remove_pending_temp_file (a signal handler): a
// fixed buffer, published by an atomic pointer, so the handler reads no half-written name.
char g_temp_name[4096];
std::atomic<const char*> g_pending_temp{nullptr};

[[noreturn]] void fail(const std::string& path, int err) {
    throw InputError(path, 0, std::string("cannot write: ") + std::strerror(err));
}

// Flushes `tmp` to the disk: errors a write deferred (a full disk on some file systems) show
// here, and a crash after the rename cannot leave an empty file under the target's name.
void sync_file(const std::string& tmp, const std::string& path) {
    const int fd = ::open(tmp.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) fail(path, errno);
    struct stat st {};
    const bool empty = ::fstat(fd, &st) == 0 && st.st_size == 0;
    const int synced = ::fsync(fd);
    const int err = errno;
    ::close(fd);
    if (synced != 0 && err != EINVAL) fail(path, err);  // EINVAL: a file system without fsync
    if (empty) throw InputError(path, 0, "cannot write: nothing was written");
}

}  // namespace

void write_atomically(const std::string& path,
                      const std::function<void(const std::string&)>& write) {
    namespace fs = std::filesystem;
    const fs::path target(path);
    const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
    if (!fs::is_directory(dir)) throw InputError(path, 0, "output directory does not exist");
    // Hidden name in the same directory, so the final rename cannot cross file systems.
    std::string name = ".";
    name.append(target.filename().string()).append(".tmp-").append(std::to_string(getpid()));
    const fs::path tmp = dir / name;
    const std::string tmp_text = tmp.string();
    if (tmp_text.size() < sizeof g_temp_name) {
        std::memcpy(g_temp_name, tmp_text.c_str(), tmp_text.size() + 1);
        g_pending_temp.store(g_temp_name);
    }
    try {
        write(tmp_text);
        sync_file(tmp_text, path);
        fs::rename(tmp, target);
        g_pending_temp.store(nullptr);
    } catch (...) {
        g_pending_temp.store(nullptr);
        std::error_code ec;
        fs::remove(tmp, ec);
        throw;
    }
}

void write_file_bytes(const std::string& path, const std::string& bytes) {
    write_atomically(path, [&](const std::string& tmp) {
        const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
        if (fd < 0) fail(path, errno);
        std::size_t done = 0;
        while (done < bytes.size()) {
            const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
            if (n < 0 && errno == EINTR) continue;
            if (n <= 0) {
                const int err = n < 0 ? errno : ENOSPC;
                ::close(fd);
                fail(path, err);
            }
            done += std::size_t(n);
        }
        if (::close(fd) != 0) fail(path, errno);
    });
}

void remove_pending_temp_file() noexcept {
    if (const char* name = g_pending_temp.exchange(nullptr)) unlink(name);
}

}  // namespace foton
