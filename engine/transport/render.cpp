#include "render.h"

#include <chrono>
#include <cstdio>
#include <thread>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <unistd.h>

#include "whitted.h"

namespace foton {

namespace {

std::vector<Tile> make_tiles(int width, int height, int size) {
    std::vector<Tile> tiles;
    for (int y = 0; y < height; y += size)
        for (int x = 0; x < width; x += size)
            tiles.push_back({x, y, std::min(x + size, width), std::min(y + size, height)});
    return tiles;
}

// Draws a progress bar with ETA on stderr until `done` reaches `total` or `stop` is set.
class ProgressBar {
  public:
    ProgressBar(const std::atomic<std::size_t>& done, std::size_t total)
        : done_(done), total_(total), thread_([this] { run(); }) {}
    ~ProgressBar() {
        stop_ = true;
        thread_.join();
        std::fprintf(stderr, "\r%*s\r", 60, "");
    }

  private:
    void run() {
        const auto start = std::chrono::steady_clock::now();
        while (!stop_) {
            std::this_thread::sleep_for(std::chrono::milliseconds(200));
            const std::size_t d = done_.load(std::memory_order_relaxed);
            const double frac = total_ ? double(d) / double(total_) : 1.0;
            const double el =
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            const double eta = frac > 0 ? el * (1.0 - frac) / frac : 0.0;
            char bar[31];
            const int fill = int(frac * 30);
            for (int i = 0; i < 30; ++i) bar[i] = i < fill ? '#' : '.';
            bar[30] = 0;
            std::fprintf(stderr, "\r[%s] %5.1f%%  %6.1fs  ETA %6.1fs", bar, 100 * frac, el, eta);
            std::fflush(stderr);
        }
    }
    const std::atomic<std::size_t>& done_;
    std::size_t total_;
    std::atomic<bool> stop_{false};
    std::thread thread_;
};

}  // namespace

int resolve_threads(int requested) {
    return requested > 0 ? requested : tbb::info::default_concurrency();
}

RenderResult render(const Scene& scene, const Intersector& accel, const RenderOptions& opt) {
    RenderResult result;
    result.film = Film(scene.film.width, scene.film.height);
    const std::vector<Tile> tiles = make_tiles(scene.film.width, scene.film.height, opt.tile_size);
    const WhittedIntegrator integrator(scene, accel, opt);
    tbb::enumerable_thread_specific<WhittedWorkspace> workspaces;
    tbb::enumerable_thread_specific<RenderStats> stats;
    std::atomic<std::size_t> done{0};
    const int threads = resolve_threads(opt.threads);

    const auto start = std::chrono::steady_clock::now();
    {
        std::unique_ptr<ProgressBar> bar;
        if (opt.progress && isatty(fileno(stderr)))
            bar = std::make_unique<ProgressBar>(done, tiles.size());
        tbb::task_arena arena(threads);
        arena.execute([&] {
            tbb::parallel_for(tbb::blocked_range<std::size_t>(0, tiles.size(), 1),
                              [&](const tbb::blocked_range<std::size_t>& r) {
                                  WhittedWorkspace& ws = workspaces.local();
                                  RenderStats& st = stats.local();
                                  for (std::size_t i = r.begin(); i != r.end(); ++i) {
                                      integrator.render_tile(tiles[i], result.film, ws, st);
                                      done.fetch_add(1, std::memory_order_relaxed);
                                  }
                              });
        });
    }
    result.stats.wall_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    for (const RenderStats& s : stats) result.stats.merge(s);
    result.stats.threads = threads;
    return result;
}

}  // namespace foton
