#pragma once
// A scaling study's data (`foton scale`): its settings, every run, and the summaries per
// thread count: wall time (median, min, max), speed-up, parallel efficiency and the
// Karp-Flatt serial fraction, overall and per stage of the render's graph.
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace foton::app {

struct ScaleArgs {
    std::string scene;
    std::string threads;  // "1,2,4", "all" (1, 2, 4, ... and every hardware thread) or ""
    std::string integrator;
    std::vector<std::string> set;  // key=value overrides of <renderer> attributes
    std::optional<std::string> spp, passes, seed, width, height;
    std::optional<float> time;  // progressive passes for this long: scaling by throughput
    std::string accel;
    uint32_t repeats = 3;
    bool weak = false;  // the work (spp, or passes when given) grows with the threads
    bool pin = false;   // one thread per CPU, physical cores first (core/thread_pinning.h)
    std::string json;   // default out/<scene>-scale.json
    std::string plot;   // SVG; default beside the JSON
    std::string command_line;
};

// One render of the sweep.
struct ScaleRun {
    int threads = 1;
    uint32_t repeat = 0;
    double wall_seconds = 0.0, build_seconds = 0.0;
    uint64_t samples = 0;
    uint32_t passes = 0;
    uint64_t image_hash = 0;  // FNV-1a of the film's bits
    // Per graph node (or, for renders without one, per stage): its time in thread-seconds
    // (a once-per-pass node's wall time times the threads it held).
    std::vector<std::pair<std::string, double>> stage_thread_seconds;
};

// A thread count's repeats, summarised.
struct ScalePoint {
    int threads = 1;
    double wall_median = 0.0, wall_min = 0.0, wall_max = 0.0;
    double rate = 0.0;  // samples per second (median run)
    // Against the first thread count t0 (ideally 1): speed-up S = t0 T(t0) / T(n) for fixed
    // work, by throughput for --time, n T(t0) / (t0 T(n)) scaled for --weak; E = S / n.
    double speedup = 1.0, efficiency = 1.0;
    double karp_flatt = 0.0;  // (1/S - 1/n) / (1 - 1/n); 0 at n = 1
    // Per stage: thread-seconds (median) and the efficiency they imply (the first count's
    // thread-seconds, times the work ratio for --weak, over these).
    std::vector<std::pair<std::string, double>> stage_thread_seconds, stage_efficiency;
};

struct ScaleStudy {
    ScaleArgs args;
    std::string integrator, settings, accel;
    int width = 0, height = 0;
    uint64_t scene_hash = 0;  // FNV-1a of the scene file
    std::vector<ScaleRun> runs;
    std::vector<ScalePoint> points;
    std::optional<bool> images_identical;  // fixed work only (not --time, not --weak)
    std::string worst_stage;               // lowest efficiency at the largest thread count
};

// Summaries of the runs (the points of `study`), from study.runs.
void summarise(ScaleStudy& study);
// The thread counts `spec` names on a machine with `hardware` threads.
std::vector<int> thread_counts(const std::string& spec, int hardware);

}  // namespace foton::app
