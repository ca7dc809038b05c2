#pragma once
// The `foton` subcommands. Each returns the process exit code; bad input is reported by
// throwing InputError, which main() turns into `file:line: problem` and exit code 2.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace foton {
class Cluster;
}

namespace foton::app {

struct RenderArgs {
    std::string scene;
    std::string output;   // .exr; empty = out/<scene name>.exr
    std::string preview;  // the tone-mapped image beside it: png (default), jpg or bmp
    // Numbers as typed: parsed and checked by the settings' integer parser (core/params.h).
    std::optional<std::string> spp, threads, seed;
    std::string accel;  // empty = the scene's <aggregate>
    std::optional<std::string> width, height;
    std::vector<double> crop;       // x0,x1,y0,y1 as fractions of the image (pbrt's)
    std::vector<int> pixel_bounds;  // x0,x1,y0,y1 in pixels
    std::string filter;             // --filter: the pixel filter
    std::string integrator;         // empty = the scene's <renderer type>
    std::string mis;
    std::string aov;      // --aov: extra outputs as EXR channels (film/aov.h)
    std::string sampler;  // --sampler: the renderer's sampler
    std::optional<bool> nee;
    std::optional<uint32_t> max_depth, rr_depth;
    std::optional<float> time;          // seconds of progressive passes
    std::optional<std::string> passes;  // progressive passes (with --time: at most this many)
    std::vector<double> snapshots;      // seconds at which to also write the image so far
    std::optional<float> adaptive;      // adaptive sampling with this relative-error threshold
    std::optional<uint32_t> adaptive_max;
    bool adaptive_unbiased = false;
    std::optional<uint32_t> light_samples;
    std::vector<std::string> set;  // key=value overrides of <renderer> attributes
    bool stats = false;
    std::string stats_json;
    std::string cache_points;            // PNG of the image with the cache's records marked white
    std::string reference;               // EXR: record each pass's error to it (convergence curve)
    std::optional<float> exclude_above;  // leave brighter reference pixels out of the error
    std::string convergence_csv;         // where the curve goes (default: beside the output)
    std::string display;                 // HOST:PORT of a tev to stream each pass to
    bool quiet = false;
    bool pin = false;          // pin each thread to a CPU of the process's affinity mask
    std::string command_line;  // as typed, for the image's metadata
};

// Across the MPI ranks of `cluster` (null: this process alone) when it has several.
int run_render(const RenderArgs& args, const Cluster* cluster = nullptr);
int run_info(const std::string& scene);

struct CompareArgs {
    std::string a, b;
    std::string diff_png;  // optional false-colour difference image
    float diff_scale = 0.1f;
    std::optional<float> exclude_above;  // leave out pixels brighter than this in b
    int exclude_margin = 0;              // ... and those within this many pixels of them
    std::string mask_png;                // count only pixels that are non-black in this PNG
    std::vector<int> lowpass;            // also the RMSE after these n x n box filters
};
int run_compare(const CompareArgs& args);

}  // namespace foton::app
