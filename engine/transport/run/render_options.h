#pragma once
// What every renderer takes (RenderOptions) and gives back (RenderResult). The families'
// render functions and the driver's loops share these types and nothing else, so the
// dispatch (render.h) can include every family without a cycle.
#include <atomic>
#include <chrono>
#include <cstdint>
#include <ctime>
#include <functional>
#include <optional>
#include <vector>

#include "engine/core/cluster.h"
#include "engine/core/math.h"
#include "engine/core/progress.h"
#include "engine/core/stats.h"
#include "engine/film/aov.h"
#include "engine/film/film.h"

namespace foton {

// Where a progressive render is after a pass, for the pass observer.
struct PassReport {
    uint32_t passes = 0;       // finished so far
    double seconds = 0.0;      // wall time of rendering (the observers' own time left out)
    double cpu_seconds = 0.0;  // CPU time of every thread, likewise
    double spp = 0.0;          // mean samples per pixel of the image so far
    bool last = false;         // no pass follows
};

// When a render began, on the wall clock and the process's CPU clock.
struct RenderStart {
    std::chrono::steady_clock::time_point wall;
    std::clock_t cpu;
    static RenderStart now() { return {std::chrono::steady_clock::now(), std::clock()}; }
};

struct RenderOptions {
    int threads = 0;  // 0 = all hardware threads
    uint64_t seed = 0;
    uint32_t spp = 1;        // samples per pixel per pass
    float time_limit = 0.f;  // > 0: passes until this many seconds have passed
    // > 0: this many passes (with a time limit: at most this many). SPPM and PPM without
    // either run `spp` passes.
    uint32_t max_passes = 0;
    int tile_size = 16;
    // Samples per pixel a camera tile carries at once: a pass of more runs in pieces (memory
    // stays bounded; the image does not depend on it).
    uint32_t chunk_spp = 256;
    Progress* progress = nullptr;  // where the render reports its tasks (a progress line)
    // Called after the first pass that ends at or after each of these times (seconds), with
    // the image so far: equal-time studies take several snapshots from one run.
    std::vector<double> snapshot_times;
    // `spp` is the mean number of samples each pixel's value averages so far.
    std::function<void(const Film&, double requested, double seconds, uint32_t passes, double spp)>
        on_snapshot;
    // Called after every pass of every integrator, the last included, with the image so far
    // (the live preview, convergence tracking). Its time is not counted as render time.
    std::function<void(const Film&, const PassReport&)> on_pass;
    // Set by a render whose passes follow work of their own (photon tracing, the cache
    // fill): the passes' times and the time budget then count from here.
    std::optional<RenderStart> start;
    // When set, the render stops after the pass in flight (a stop button, a signal).
    const std::atomic<bool>* cancel = nullptr;
    // The MPI ranks this render is split across (null: this process alone). Each rank
    // renders its share; rank 0 ends with the image, the same bit for bit as one process's.
    const Cluster* cluster = nullptr;
};

struct RenderResult {
    Film film;
    RenderStats stats;
    std::vector<uint32_t> samples_per_pixel;  // what each pixel's value averages
    std::vector<Vec3> cache_points;           // the irradiance cache's records (first level)
    std::vector<AovLayer> aovs;               // the extra outputs asked for (film/aov.h)
};

// The most worker threads a render runs (oneTBB itself fails beyond 65,536).
constexpr int kMaxThreads = 4096;
// The most samples per pixel of a pass (spp, aa_samples, the adaptive pilot) and the most
// progressive passes a render takes: the settings, the command line and `foton serve` check
// against these.
constexpr uint64_t kMaxSamplesPerPass = 100000000;
constexpr uint32_t kMaxPasses = 1u << 30;

// The worker count to run with: `requested`, or every hardware thread for 0.
int resolve_threads(int requested);

}  // namespace foton
