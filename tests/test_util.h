#pragma once
// Helpers shared by the tests: paths to the project and to ../shared, temporary files.
#include <sys/wait.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <random>
#include <string>

#include "engine/accel/intersector.h"
#include "engine/scene/scene.h"
#include "engine/transport/registry/integrators.h"
#include "engine/transport/registry/render.h"

namespace foton {
// A scene with its renderer settings typed, for tests that adjust them
// (s.render.photon.k = 50) and render with render(s, s.render, accel, opt).
struct TestScene : Scene {
    RenderSettings render;
    TestScene(Scene scene) : Scene(std::move(scene)), render(render_settings(*this)) {}
};

// Renders `scene` with its own settings: spp samples per pixel, `threads` (0 = all), `seed`.
inline RenderResult render_test(const TestScene& scene, uint32_t spp, int threads = 0,
                                uint64_t seed = 1) {
    const auto acc = make_intersector(scene, scene.accel);
    RenderOptions opt;
    opt.spp = spp;
    opt.threads = threads;
    opt.seed = seed;
    return render(scene, scene.render, *acc, opt);
}
}  // namespace foton

namespace foton::test {

// Under the sanitizers the brute-force oracles run some 50x slower: loops that compare
// against them take every 16th case there, and all of them in normal builds.
#ifdef FOTON_SANITIZED
inline constexpr int kSanitizedStride = 16;
#else
inline constexpr int kSanitizedStride = 1;
#endif
inline constexpr int scaled(int n) {
    return n / kSanitizedStride > 0 ? n / kSanitizedStride : 1;
}

// How much more work than the default the statistical tests that read it should do:
// FOTON_TEST_EFFORT=16 renders 16x the samples (a quarter of the noise) for a thorough run
// outside CI; 1 when unset.
inline uint32_t effort() {
    const char* e = std::getenv("FOTON_TEST_EFFORT");
    const long n = e ? std::strtol(e, nullptr, 10) : 1;
    return n >= 1 && n <= 1 << 16 ? uint32_t(n) : 1u;
}

inline std::string source_path(const std::string& rel) {
    return std::string(FOTON_SOURCE_DIR) + "/" + rel;
}
inline std::string shared_path(const std::string& rel) {
    return std::string(FOTON_SOURCE_DIR) + "/../shared/" + rel;
}

// The foton program run with `args` (a shell command line), its exit code and its stdout and
// stderr together.
struct FotonRun {
    int code = -1;
    std::string output;
};
inline FotonRun run_foton(const std::string& args) {
    const std::string cmd = std::string(FOTON_BINARY) + " " + args + " 2>&1";
    FILE* p = popen(cmd.c_str(), "r");
    FotonRun r;
    if (!p) return r;
    char buf[4096];
    while (std::size_t n = std::fread(buf, 1, sizeof buf, p)) r.output.append(buf, n);
    const int status = pclose(p);
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return r;
}

// A fresh empty directory under the system temp dir, removed with the object.
class TempDir {
  public:
    TempDir() {
        std::random_device rd;
        path_ = std::filesystem::temp_directory_path() / ("foton-test-" + std::to_string(rd()));
        std::filesystem::create_directories(path_);
    }
    ~TempDir() {
        std::error_code ec;
        std::filesystem::remove_all(path_, ec);
    }
    std::string file(const std::string& name) const { return (path_ / name).string(); }
    const std::filesystem::path& path() const { return path_; }

  private:
    std::filesystem::path path_;
};

}  // namespace foton::test
