#pragma once
// What every renderer takes (RenderOptions) and gives back (RenderResult). The families'
// render functions and the driver's loops share these types and nothing else, so the
// dispatch (render.h) can include every family without a cycle.
#include <cstdint>
#include <functional>
#include <vector>

#include "engine/core/math.h"
#include "engine/core/stats.h"
#include "engine/film/film.h"

namespace foton {

struct RenderOptions {
    int threads = 0;  // 0 = all hardware threads
    uint64_t seed = 0;
    uint32_t spp = 1;         // samples per pixel per pass
    float time_limit = 0.f;   // > 0: passes until this many seconds have passed
    uint32_t max_passes = 0;  // > 0: stop after this many passes (with or without a time)
    int tile_size = 16;
    bool progress = false;  // progress bar and ETA on stderr
    // Called after the first pass that ends at or after each of these times (seconds), with
    // the image so far: equal-time studies take several snapshots from one run.
    std::vector<double> snapshot_times;
    // `spp` is the mean number of samples each pixel's value averages so far.
    std::function<void(const Film&, double requested, double seconds, uint32_t passes, double spp)>
        on_snapshot;
};

struct RenderResult {
    Film film;
    RenderStats stats;
    std::vector<uint32_t> samples_per_pixel;  // what each pixel's value averages
    std::vector<Vec3> cache_points;           // the irradiance cache's records (first level)
};

// The worker count to run with: `requested`, or every hardware thread for 0.
int resolve_threads(int requested);

}  // namespace foton
