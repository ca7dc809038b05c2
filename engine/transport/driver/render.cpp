#include "render.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <thread>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <unistd.h>

#include <tbb/flow_graph.h>
#include <tbb/parallel_invoke.h>

#include "engine/core/error.h"
#include "engine/scene/light_set.h"
#include "engine/transport/irradiance_cache/cache_evaluator.h"
#include "engine/transport/irradiance_cache/cache_fill.h"
#include "engine/transport/light/light_tracer.h"
#include "engine/transport/path/path.h"
#include "engine/transport/photon/photon_integrator.h"
#include "engine/transport/photon/photon_tracer.h"
#include "engine/transport/photon/sppm.h"
#include "engine/transport/whitted/whitted.h"

namespace foton {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

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
        const auto start = Clock::now();
        while (!stop_) {
            std::this_thread::sleep_for(std::chrono::milliseconds(200));
            const std::size_t d = done_.load(std::memory_order_relaxed);
            const double frac = total_ ? std::min(1.0, double(d) / double(total_)) : 1.0;
            const double el = seconds_since(start);
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

// Decides when the progressive loop stops and fires the snapshots.
class PassControl {
  public:
    PassControl(const RenderOptions& opt) : opt_(opt), start_(Clock::now()) {}
    double elapsed() const { return seconds_since(start_); }
    // After pass `passes` (1-based) has finished: whether to run another.
    bool another(uint32_t passes, const std::function<Film()>& image) {
        const double t = elapsed();
        while (next_snapshot_ < opt_.snapshot_times.size() &&
               t >= opt_.snapshot_times[next_snapshot_]) {
            if (opt_.on_snapshot)
                opt_.on_snapshot(image(), opt_.snapshot_times[next_snapshot_], t, passes);
            ++next_snapshot_;
        }
        if (opt_.max_passes > 0 && passes >= opt_.max_passes) return false;
        return opt_.time_limit > 0.f && t < double(opt_.time_limit);
    }

  private:
    const RenderOptions& opt_;
    Clock::time_point start_;
    std::size_t next_snapshot_ = 0;
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

RenderResult render_light(const Scene& scene, const Intersector& accel, const RenderOptions& opt) {
    if (scene.camera.type != CameraType::Perspective || scene.camera.lens_radius > 0.f)
        throw InputError(scene.source, 0,
                         "the light tracer needs a pinhole perspective camera (no lens_radius)");
    const LightSet lights(scene);
    if (lights.empty()) throw InputError(scene.source, 0, "the light tracer needs a light");
    const LightTracer tracer(scene, accel, lights, opt.seed);
    const int threads = resolve_threads(opt.threads);
    const uint64_t per_pass =
        uint64_t(scene.film.width) * uint64_t(scene.film.height) * uint64_t(opt.spp);
    constexpr uint32_t kChunk = 4096;
    const std::size_t chunks = std::size_t((per_pass + kChunk - 1) / kChunk);
    std::vector<RGB> sum(std::size_t(scene.film.width) * scene.film.height);
    std::vector<std::vector<Splat>> splats(chunks);
    tbb::enumerable_thread_specific<LightTracerWorkspace> workspaces;
    tbb::enumerable_thread_specific<RenderStats> stats;
    PassControl control(opt);
    uint32_t passes = 0;
    auto image = [&] {
        Film f(scene.film.width, scene.film.height);
        // A pixel's estimate is its splat sum over the number of paths traced.
        const float inv = float(1.0 / (double(per_pass) * passes));
        for (std::size_t i = 0; i < sum.size(); ++i) f.pixels[i] = sum[i] * inv;
        return f;
    };
    tbb::task_arena arena(threads);
    do {
        const uint64_t base = uint64_t(passes) * per_pass;
        arena.execute([&] {
            tbb::parallel_for(tbb::blocked_range<std::size_t>(0, chunks, 1),
                              [&](const tbb::blocked_range<std::size_t>& r) {
                                  LightTracerWorkspace& ws = workspaces.local();
                                  RenderStats& st = stats.local();
                                  for (std::size_t c = r.begin(); c != r.end(); ++c) {
                                      const uint64_t first = uint64_t(c) * kChunk;
                                      const uint32_t n =
                                          uint32_t(std::min<uint64_t>(kChunk, per_pass - first));
                                      splats[c].clear();
                                      tracer.trace(base + first, n, ws, splats[c], st);
                                  }
                              });
        });
        StageClock clock;
        std::size_t count = 0;
        for (const std::vector<Splat>& list : splats) {
            for (const Splat& s : list) sum[s.pixel] += s.value;
            count += list.size();
        }
        RenderStats& st = stats.local();
        st.add(Stage::Accumulate, count, clock);
        ++passes;
    } while (control.another(passes, image));
    RenderResult result;
    result.stats.wall_seconds = control.elapsed();
    for (const RenderStats& s : stats) result.stats.merge(s);
    result.stats.threads = threads;
    result.stats.passes = passes;
    result.film = image();
    result.samples_per_pixel.assign(sum.size(), opt.spp * passes);
    return result;
}

// Photon mapping as a job graph: the global and caustic passes (emit, trace and store,
// parallel inside) run side by side, each feeds the balancing of its kd-tree, the global
// tree feeds the precomputed irradiance, and all of it feeds the camera pass.
// The secondary evaluation the scene asks for, checked against the renderer.
CacheSecondary cache_secondary(const Scene& scene) {
    const CacheSecondary m = scene.render.cache.secondary;
    const bool photon = scene.render.integrator == IntegratorType::Photon;
    if (m == CacheSecondary::Auto) return photon ? CacheSecondary::Photon : CacheSecondary::Path;
    if (m == CacheSecondary::Photon && !photon)
        throw InputError(
            "renderer", 0,
            "cache_secondary=\"photon\" needs type=\"photon\" (there is no photon map)");
    return m;
}

// Renders through `integrator` with an irradiance cache: one cache per level, filled in
// hierarchical passes, then read (frozen) by the image pass. `attach` hands the evaluator
// to the integrator.
RenderResult render_with_cache(const Scene& scene, const Intersector& accel, const LightSet& lights,
                               const CameraIntegrator& integrator,
                               const std::function<void(const CacheEvaluator*)>& attach,
                               CacheEvaluator::PhotonRadiance photons, const RenderOptions& opt) {
    const PathIntegrator onwards(scene, accel, lights, opt.seed, false);
    CacheEvaluator evaluator(scene, accel, lights, opt.seed, cache_secondary(scene),
                             std::move(photons), &onwards);
    std::vector<IrradianceCache> caches(
        evaluator.levels(), IrradianceCache(scene.bounds(), cache_params(scene.render.cache)));
    std::vector<const IrradianceCache*> frozen;
    for (const IrradianceCache& c : caches) frozen.push_back(&c);
    evaluator.set_caches(frozen);
    attach(&evaluator);
    RenderStats fill_stats;
    const auto t0 = Clock::now();
    fill_irradiance_cache(scene, integrator, caches, opt.spp, resolve_threads(opt.threads),
                          fill_stats);
    const double fill_seconds = seconds_since(t0);
    RenderResult result = render_camera(scene, integrator, opt);
    attach(nullptr);
    result.stats.merge(fill_stats);
    result.stats.wall_seconds += fill_seconds;
    result.stats.cache_fill_seconds = fill_seconds;
    for (const IrradianceCache& c : caches) result.stats.cache_stored += c.size();
    for (std::size_t i = 0; i < caches[0].size(); ++i)
        result.cache_points.push_back(caches[0].record(i).p);
    return result;
}

RenderResult render_photon(const Scene& scene, const Intersector& accel, const RenderOptions& opt) {
    const PhotonSettings& ps = scene.render.photon;
    const LightSet lights(scene);
    if (lights.empty()) throw InputError(scene.source, 0, "photon mapping needs a light");
    const PhotonTracer tracer(scene, accel, lights, opt.seed);
    const float radius = 0.5f * length(scene.bounds().diagonal());
    PhotonMaps maps;
    EstimateParams& gp = maps.global_params;
    gp.k = ps.k;
    gp.max_radius = ps.max_radius > 0.f ? ps.max_radius : 0.05f * radius;
    gp.envelope = PhotonEnvelope(ps.envelope);
    gp.filter = PhotonFilter(ps.filter);
    gp.cone_k = ps.cone_k;
    EstimateParams& cp = maps.caustic_params;
    cp = gp;
    cp.k = ps.caustic_k;
    cp.max_radius = ps.caustic_radius > 0.f ? ps.caustic_radius : 0.02f * radius;
    cp.filter = PhotonFilter(ps.caustic_filter);

    RenderStats photon_stats, global_stats, caustic_stats;
    const int threads = resolve_threads(opt.threads);
    const kern::PointKdTree::ParallelInvoke par = [](const std::function<void()>& a,
                                                     const std::function<void()>& b) {
        tbb::parallel_invoke(a, b);
    };
    const auto start = Clock::now();
    tbb::task_arena arena(threads);
    arena.execute([&] {
        using Node = tbb::flow::continue_node<tbb::flow::continue_msg>;
        using Msg = const tbb::flow::continue_msg&;
        tbb::flow::graph g;
        tbb::flow::broadcast_node<tbb::flow::continue_msg> start_node(g);
        Node trace_global(g, [&](Msg) {
            PhotonPassSettings s;
            s.kind = PhotonMapKind::Global;
            s.emitted = ps.global_photons;
            s.max_depth = scene.render.max_depth;
            s.unscaled_roulette = ps.unscaled_roulette;
            s.pass = 0;
            s.shadow_photons = ps.shadow_photons;
            if (s.emitted > 0) maps.global = tracer.run(s, global_stats, &maps.shadow);
            if (ps.split_direct) maps.direct = maps.global.extract(kPhotonDirect);
        });
        Node trace_caustic(g, [&](Msg) {
            PhotonPassSettings s;
            s.kind = PhotonMapKind::Caustic;
            s.emitted = ps.caustic_photons;
            s.max_depth = scene.render.max_depth;
            s.unscaled_roulette = ps.unscaled_roulette;
            s.pass = 1;
            // The direct-visualisation mode reads the global map only.
            if (s.emitted > 0 && ps.mode == PhotonMode::FinalGather)
                maps.caustic = tracer.run(s, caustic_stats);
        });
        Node balance_global(g, [&](Msg) {
            StageClock c;
            maps.global.build(par);
            maps.direct.build(par);
            maps.shadow.build(par);
            global_stats.add(Stage::Balance,
                             maps.global.size() + maps.direct.size() + maps.shadow.size(), c);
        });
        Node precompute(g, [&](Msg) {
            if (ps.mode != PhotonMode::FinalGather || ps.irradiance_stride == 0) return;
            StageClock c;
            const auto parallel_for =
                [](std::size_t n, const std::function<void(std::size_t, std::size_t)>& body) {
                    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1024),
                                      [&](const tbb::blocked_range<std::size_t>& r) {
                                          body(r.begin(), r.end());
                                      });
                };
            maps.global.precompute_irradiance(ps.irradiance_stride, gp, parallel_for);
            if (!maps.direct.empty())
                maps.direct.precompute_irradiance(ps.irradiance_stride, gp, parallel_for);
            global_stats.add(Stage::Precompute,
                             maps.global.precomputed_size() + maps.direct.precomputed_size(), c);
        });
        Node balance_caustic(g, [&](Msg) {
            StageClock c;
            maps.caustic.build(par);
            caustic_stats.add(Stage::Balance, maps.caustic.size(), c);
        });
        Node done(g, [](Msg) {});
        tbb::flow::make_edge(start_node, trace_global);
        tbb::flow::make_edge(start_node, trace_caustic);
        tbb::flow::make_edge(trace_global, balance_global);
        tbb::flow::make_edge(trace_caustic, balance_caustic);
        tbb::flow::make_edge(balance_global, precompute);
        tbb::flow::make_edge(precompute, done);
        tbb::flow::make_edge(balance_caustic, done);
        start_node.try_put(tbb::flow::continue_msg());
        g.wait_for_all();
    });
    const double photon_seconds = seconds_since(start);
    photon_stats.merge(global_stats);
    photon_stats.merge(caustic_stats);

    PhotonIntegrator integrator(scene, accel, lights, maps, opt.seed);
    RenderResult result = scene.render.indirect == IndirectMode::IrradianceCache
                              ? render_with_cache(
                                    scene, accel, lights, integrator,
                                    [&](const CacheEvaluator* e) { integrator.set_cache(e); },
                                    [&](const SurfacePoint& sp, const Material& m, const Vec3& d) {
                                        return integrator.photon_radiance(sp, m, d);
                                    },
                                    opt)
                              : render_camera(scene, integrator, opt);
    result.stats.merge(photon_stats);
    result.stats.wall_seconds += photon_seconds;
    result.stats.photons_global = maps.global.size() + maps.direct.size();
    result.stats.photons_caustic = maps.caustic.size();
    result.stats.photon_seconds = photon_seconds;
    return result;
}

}  // namespace

int resolve_threads(int requested) {
    return requested > 0 ? requested : tbb::info::default_concurrency();
}

RenderResult render(const Scene& scene, const Intersector& accel, const RenderOptions& opt) {
    if (scene.render.indirect == IndirectMode::IrradianceCache) {
        const IntegratorType t = scene.render.integrator;
        if (!(t == IntegratorType::Path ||
              (t == IntegratorType::Photon && scene.render.photon.mode == PhotonMode::FinalGather)))
            throw InputError("renderer", 0,
                             "indirect=\"irradiance_cache\" needs type=\"path\" or type=\"photon\" "
                             "in final-gather mode");
    }
    switch (scene.render.integrator) {
        case IntegratorType::Light:
            return render_light(scene, accel, opt);
        case IntegratorType::Photon:
            return render_photon(scene, accel, opt);
        case IntegratorType::Sppm:
        case IntegratorType::Ppm:
            return render_progressive_photons(scene, accel, opt);
        case IntegratorType::Path:
        case IntegratorType::Distributed: {
            const LightSet lights(scene);
            PathIntegrator integrator(scene, accel, lights, opt.seed,
                                      scene.render.integrator == IntegratorType::Distributed);
            if (scene.render.indirect == IndirectMode::IrradianceCache)
                return render_with_cache(
                    scene, accel, lights, integrator,
                    [&](const CacheEvaluator* e) { integrator.set_cache(e); }, nullptr, opt);
            return render_camera(scene, integrator, opt);
        }
        case IntegratorType::Whitted:
            break;
    }
    const WhittedIntegrator integrator(scene, accel, opt.seed);
    return render_camera(scene, integrator, opt);
}

}  // namespace foton
