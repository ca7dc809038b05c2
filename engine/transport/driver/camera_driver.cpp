#include "camera_driver.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <memory>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <unistd.h>

#include "pass_control.h"
#include "progress_bar.h"

namespace foton {

namespace {

struct Tile {
    int x0, y0, x1, y1;  // pixel rectangle [x0, x1) x [y0, y1)
    int pixels() const { return (x1 - x0) * (y1 - y0); }
};

std::vector<Tile> make_tiles(int width, int height, int size) {
    std::vector<Tile> tiles;
    for (int y = 0; y < height; y += size)
        for (int x = 0; x < width; x += size)
            tiles.push_back({x, y, std::min(x + size, width), std::min(y + size, height)});
    return tiles;
}

// Running sums of the samples of every pixel: the image is sum / count.
struct Accumulator {
    int width = 0, height = 0;
    std::vector<RGB> sum;
    std::vector<uint32_t> count;
    Accumulator(int w, int h)
        : width(w), height(h), sum(std::size_t(w) * h), count(std::size_t(w) * h, 0) {}
    Film film() const {
        Film f(width, height);
        for (std::size_t i = 0; i < sum.size(); ++i)
            f.pixels[i] = count[i] ? sum[i] * (1.f / float(count[i])) : RGB{0.f};
        return f;
    }
};

// Luminance statistics of one pixel's samples, for adaptive sampling.
struct PixelMoments {
    double sum = 0.0, sum2 = 0.0;
    uint32_t n = 0;
    void add(float y) {
        sum += y;
        sum2 += double(y) * y;
        ++n;
    }
    double mean() const { return n ? sum / n : 0.0; }
    // Unbiased sample variance of one sample (the thesis' s^2 times N).
    double variance() const {
        if (n < 2) return 0.0;
        return std::max(0.0, (sum2 - sum * sum / n) / (n - 1));
    }
    // Standard error of the mean relative to the mean (absolute below a small floor).
    double relative_error() const {
        return std::sqrt(variance() / std::max<uint32_t>(n, 1)) / std::max(mean(), 1e-3);
    }
};

class CameraDriver {
  public:
    CameraDriver(const Scene& scene, const CameraIntegrator& integrator, const RenderOptions& opt)
        : scene_(scene), integrator_(integrator), opt_(opt) {}

    // Fixed samples: pass p gives every pixel of the tile opt.spp samples.
    void fixed_pass(const Tile& t, uint32_t pass, Accumulator& acc, IntegratorWorkspace& ws,
                    RenderStats& st, std::vector<SampleJob>& jobs, std::vector<RGB>& out) const {
        const uint32_t spp = opt_.spp;
        const uint64_t npix = uint64_t(scene_.film.width) * uint64_t(scene_.film.height);
        jobs.clear();
        for (int y = t.y0; y < t.y1; ++y)
            for (int x = t.x0; x < t.x1; ++x) {
                const uint64_t pixel = uint64_t(y) * uint64_t(scene_.film.width) + uint64_t(x);
                for (uint32_t s = 0; s < spp; ++s)
                    jobs.push_back({uint32_t(x), uint32_t(y), s, spp, pass,
                                    (uint64_t(pass) * npix + pixel) * spp + s});
            }
        integrator_.trace(jobs, ws, out, st);
        StageClock clock;
        for (std::size_t i = 0; i < jobs.size(); ++i) {
            const std::size_t p = std::size_t(jobs[i].y) * scene_.film.width + jobs[i].x;
            acc.sum[p] += out[i];
            acc.count[p] += 1;
        }
        st.samples += jobs.size();
        st.add(Stage::Accumulate, jobs.size(), clock);
    }

    // Adaptive sampling of one tile (the thesis' section 6.2): a pilot of `pilot` samples
    // per pixel, then either rounds that double the samples of every pixel whose relative
    // standard error is above the threshold (biased: the stopping rule sees the samples it
    // averages), or, unbiased (Kirk & Arvo), one fresh batch sized from the pilot's variance
    // with the pilot discarded.
    void adaptive_tile(const Tile& t, Accumulator& acc, IntegratorWorkspace& ws, RenderStats& st,
                       std::vector<SampleJob>& jobs, std::vector<RGB>& out) const {
        const AdaptiveSettings& ad = scene_.render.adaptive;
        const int tw = t.x1 - t.x0;
        std::vector<PixelMoments> mom(std::size_t(t.pixels()));
        std::vector<RGB> sum(std::size_t(t.pixels()));
        std::vector<uint32_t> want(std::size_t(t.pixels()), ad.pilot);
        std::vector<uint32_t> taken(std::size_t(t.pixels()), 0);
        auto local = [&](const SampleJob& j) {
            return std::size_t(j.y - t.y0) * tw + (j.x - t.x0);
        };
        auto run_round = [&](uint32_t round) {
            jobs.clear();
            for (int y = t.y0; y < t.y1; ++y)
                for (int x = t.x0; x < t.x1; ++x) {
                    const std::size_t l = std::size_t(y - t.y0) * tw + (x - t.x0);
                    const uint64_t pixel = uint64_t(y) * uint64_t(scene_.film.width) + uint64_t(x);
                    for (uint32_t s = 0; s < want[l]; ++s)
                        jobs.push_back({uint32_t(x), uint32_t(y), s, want[l], round,
                                        (pixel << 24) + taken[l] + s});
                    taken[l] += want[l];
                }
            if (jobs.empty()) return false;
            integrator_.trace(jobs, ws, out, st);
            st.samples += jobs.size();
            for (std::size_t i = 0; i < jobs.size(); ++i) {
                const std::size_t l = local(jobs[i]);
                mom[l].add(out[i].luminance());
                sum[l] += out[i];
            }
            return true;
        };
        run_round(0);
        if (ad.unbiased) {
            // Samples needed for the target error, from the pilot's variance; then a fresh
            // estimate from only those.
            for (std::size_t l = 0; l < mom.size(); ++l) {
                const double target = ad.threshold * std::max(mom[l].mean(), 1e-3);
                const double n = std::ceil(mom[l].variance() / (target * target));
                want[l] = uint32_t(std::clamp(n, 1.0, double(ad.max_spp - ad.pilot)));
                if (ad.max_spp == ad.pilot) want[l] = 0;
                if (want[l] > 0) {
                    mom[l] = {};
                    sum[l] = RGB{0.f};
                }
            }
            run_round(1);
        } else {
            for (uint32_t round = 1;; ++round) {
                for (std::size_t l = 0; l < mom.size(); ++l) {
                    const bool noisy = mom[l].relative_error() > ad.threshold;
                    want[l] = noisy ? std::min(mom[l].n, ad.max_spp - mom[l].n) : 0;
                }
                if (!run_round(round)) break;
            }
        }
        for (int y = t.y0; y < t.y1; ++y)
            for (int x = t.x0; x < t.x1; ++x) {
                const std::size_t l = std::size_t(y - t.y0) * tw + (x - t.x0);
                const std::size_t p = std::size_t(y) * scene_.film.width + x;
                acc.sum[p] += sum[l];
                acc.count[p] += mom[l].n;
            }
    }

  private:
    const Scene& scene_;
    const CameraIntegrator& integrator_;
    const RenderOptions& opt_;
};

}  // namespace

RenderResult render_camera(const Scene& scene, const CameraIntegrator& integrator,
                           const RenderOptions& opt) {
    RenderResult result;
    Accumulator acc(scene.film.width, scene.film.height);
    const std::vector<Tile> tiles = make_tiles(scene.film.width, scene.film.height, opt.tile_size);
    const CameraDriver driver(scene, integrator, opt);
    struct Scratch {
        std::unique_ptr<IntegratorWorkspace> ws;
        std::vector<SampleJob> jobs;
        std::vector<RGB> out;
    };
    tbb::enumerable_thread_specific<Scratch> scratch;
    tbb::enumerable_thread_specific<RenderStats> stats;
    std::atomic<std::size_t> done{0};
    const int threads = resolve_threads(opt.threads);
    const bool adaptive = scene.render.adaptive.enabled;
    const bool progressive = opt.time_limit > 0.f || opt.max_passes > 1;

    PassControl control(opt);
    uint32_t passes = 0;
    {
        std::unique_ptr<ProgressBar> bar;
        if (opt.progress && !progressive && isatty(fileno(stderr)))
            bar = std::make_unique<ProgressBar>(done, tiles.size());
        tbb::task_arena arena(threads);
        do {
            const uint32_t pass = passes;
            arena.execute([&] {
                tbb::parallel_for(
                    tbb::blocked_range<std::size_t>(0, tiles.size(), 1),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                        Scratch& s = scratch.local();
                        if (!s.ws) s.ws = integrator.make_workspace();
                        RenderStats& st = stats.local();
                        for (std::size_t i = r.begin(); i != r.end(); ++i) {
                            if (adaptive)
                                driver.adaptive_tile(tiles[i], acc, *s.ws, st, s.jobs, s.out);
                            else
                                driver.fixed_pass(tiles[i], pass, acc, *s.ws, st, s.jobs, s.out);
                            done.fetch_add(1, std::memory_order_relaxed);
                        }
                    });
            });
            ++passes;
        } while (!adaptive && control.another(passes, [&] { return acc.film(); }));
    }
    result.stats.wall_seconds = control.elapsed();
    for (const RenderStats& s : stats) result.stats.merge(s);
    result.stats.threads = threads;
    result.stats.passes = passes;
    result.film = acc.film();
    result.samples_per_pixel = acc.count;
    return result;
}

}  // namespace foton
