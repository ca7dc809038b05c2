#pragma once
// Rendering entry point shared by the integrators: the image is cut into tiles, tiles run
// in parallel on oneTBB inside a task_arena of the requested size, and every tile is
// rendered as a wavefront of ray batches. Tiles own their pixels and all random numbers
// are counter-based, so the image is bit-identical for any thread count.
#include <atomic>
#include <cstdint>
#include <functional>

#include "engine/accel/intersector.h"
#include "engine/core/stats.h"
#include "engine/film/film.h"
#include "engine/scene/scene.h"

namespace foton {

struct RenderOptions {
    int threads = 0;  // 0 = all hardware threads
    uint64_t seed = 0;
    uint32_t spp = 1;
    int tile_size = 16;
    bool progress = false;  // progress bar and ETA on stderr
};

struct Tile {
    int x0, y0, x1, y1;  // pixel rectangle [x0, x1) x [y0, y1)
    int pixels() const { return (x1 - x0) * (y1 - y0); }
};

struct RenderResult {
    Film film;
    RenderStats stats;
};

int resolve_threads(int requested);

RenderResult render(const Scene& scene, const Intersector& accel, const RenderOptions& options);

}  // namespace foton
