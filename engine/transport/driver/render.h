#pragma once
// Rendering entry point shared by the integrators. Camera integrators: the image is cut into
// tiles, tiles run in parallel on oneTBB inside a task_arena of the requested size, and every
// tile's samples are traced as a wavefront of ray batches; a pass gives every pixel `spp`
// samples (or, adaptive, as many as its error asks for), and `time_limit` repeats passes
// until the time is up. The light tracer runs passes of width x height x spp light paths in
// fixed chunks. Tiles own their pixels, chunks merge in order, and all random numbers are
// counter-based, so the image is bit-identical for any thread count.
#include <atomic>
#include <cstdint>
#include <functional>
#include <vector>

#include "engine/accel/intersector.h"
#include "engine/core/stats.h"
#include "engine/film/film.h"
#include "engine/scene/scene.h"

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
    std::function<void(const Film&, double requested, double seconds, uint32_t passes)> on_snapshot;
};

struct Tile {
    int x0, y0, x1, y1;  // pixel rectangle [x0, x1) x [y0, y1)
    int pixels() const { return (x1 - x0) * (y1 - y0); }
};

struct RenderResult {
    Film film;
    RenderStats stats;
    std::vector<uint32_t> samples_per_pixel;  // what each pixel's value averages
    std::vector<Vec3> cache_points;           // the irradiance cache's records (first level)
};

int resolve_threads(int requested);

// Renders with the scene's integrator and settings (scene.render).
RenderResult render(const Scene& scene, const Intersector& accel, const RenderOptions& options);

}  // namespace foton
