#pragma once
// `foton serve`: the ray-tracing thesis' GUI as a local web page. One render at a time, run
// on a thread of the server; the page polls its status and preview. Scenes come only from the
// folders given, by name: the server never reads a path the page sends.
#include <cstddef>
#include <string>
#include <vector>

namespace foton::app {

struct ServeArgs {
    std::string host = "127.0.0.1";
    int port = 8080;                      // 0: any free port (printed)
    std::vector<std::string> scene_dirs;  // default: scenes/
    // Folders besides scene_dirs whose files scenes may read (meshes, textures); every other
    // path is refused (core/input_file.h's confine_inputs). Default with the default
    // scenes/: ../shared when it exists (the repository's scenes read its meshes).
    std::vector<std::string> allow_read;
    // Listening beyond this machine (a --host other than loopback) lets anyone on that
    // network start renders: it needs this, and prints a warning.
    bool allow_remote = false;
};

// The largest request body the server reads (a form of a few settings fits in a few KB).
inline constexpr std::size_t kMaxRequestBody = 1 << 20;
// Worker threads, and how long a connection may take to send its request.
inline constexpr std::size_t kServeWorkers = 64;
inline constexpr int kServeReadTimeoutSeconds = 2;

int run_serve(const ServeArgs& args);

}  // namespace foton::app
