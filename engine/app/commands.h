#pragma once
// The `foton` subcommands. Each returns the process exit code; bad input is reported by
// throwing InputError, which main() turns into `file:line: problem` and exit code 2.
#include <cstdint>
#include <optional>
#include <string>

namespace foton::app {

struct RenderArgs {
    std::string scene;
    std::string output;  // .exr; empty = out/<scene name>.exr
    std::optional<uint32_t> spp;
    std::optional<int> threads;
    std::optional<uint64_t> seed;
    std::string accel;  // empty = the scene's <aggregate>
    std::optional<int> width, height;
    bool stats = false;
    std::string stats_json;
    bool quiet = false;
};

int run_render(const RenderArgs& args);
int run_info(const std::string& scene);

struct CompareArgs {
    std::string a, b;
    std::string diff_png;  // optional false-colour difference image
    float diff_scale = 0.1f;
};
int run_compare(const CompareArgs& args);

}  // namespace foton::app
