#include "camera_driver.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <memory>

#include <tbb/concurrent_queue.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/flow_graph.h>
#include <tbb/task_arena.h>

#include "adaptive_tile.h"
#include "camera_tile.h"
#include "engine/core/thread_pinning.h"
#include "engine/film/pixel_sums.h"
#include "pass_control.h"

namespace foton {

namespace {

class CameraDriver {
  public:
    CameraDriver(const Scene& scene, const RenderOptions& opt) : scene_(scene), opt_(opt) {}

    // Fixed samples: pass p gives every pixel of the tile opt.spp samples, [s0, s1) of them
    // in this piece of the pass.
    void make_jobs(const Tile& t, uint32_t pass, uint32_t s0, uint32_t s1,
                   std::vector<SampleJob>& jobs) const {
        jobs.clear();
        append_pass_jobs(scene_.film, t, pass, s0, s1, opt_.spp, jobs);
    }

    // The samples' radiance, and their components to `parts` (one sum per component).
    // With `weights` (a filter with negative lobes) each sample and its components count
    // with its weight (PixelSums' weighted mean).
    void accumulate_samples(const std::vector<SampleJob>& jobs, const std::vector<RGB>& out,
                            const std::vector<float>& weights, const IntegratorWorkspace& ws,
                            PixelSums& acc, std::vector<PixelSums>& parts, RenderStats& st) const {
        StageClock clock;
        for (std::size_t i = 0; i < jobs.size(); ++i) {
            const std::size_t p = std::size_t(jobs[i].y) * scene_.film.width + jobs[i].x;
            if (weights.empty()) {
                acc.add_sample(p, out[i]);
                for (std::size_t c = 0; c < parts.size(); ++c)
                    parts[c].add(p, ws.parts[i * parts.size() + c]);
                continue;
            }
            acc.add_sample(p, out[i], weights[i]);
            for (std::size_t c = 0; c < parts.size(); ++c) {
                parts[c].add(p, ws.parts[i * parts.size() + c] * weights[i]);
                parts[c].add_weight(p, weights[i]);
            }
        }
        st.samples += jobs.size();
        st.add(Stage::Accumulate, jobs.size(), clock);
    }

    void accumulate_tile(const Tile& t, const TileSums& sums, PixelSums& acc,
                         std::vector<PixelSums>& parts, RenderStats& st) const {
        StageClock clock;
        const int tw = t.x1 - t.x0;
        for (int y = t.y0; y < t.y1; ++y)
            for (int x = t.x0; x < t.x1; ++x) {
                const std::size_t l = std::size_t(y - t.y0) * tw + (x - t.x0);
                const std::size_t p = std::size_t(y) * scene_.film.width + x;
                acc.add(p, sums.sum[l], sums.count[l], sums.moments[l]);
                if (!sums.weight.empty()) acc.add_weight(p, sums.weight[l]);
                for (std::size_t c = 0; c < parts.size(); ++c) {
                    parts[c].add(p, sums.parts[l * parts.size() + c], sums.count[l]);
                    if (!sums.weight.empty()) parts[c].add_weight(p, sums.weight[l]);
                }
            }
        st.add(Stage::Accumulate, std::size_t(t.pixels()), clock);
    }

  private:
    const Scene& scene_;
    const RenderOptions& opt_;
};

double mean_count(const std::vector<uint32_t>& count) {
    double sum = 0.0;
    for (uint32_t c : count) sum += c;
    return count.empty() ? 0.0 : sum / double(count.size());
}

}  // namespace

RenderResult render_camera(const Scene& scene, const RenderSettings& settings,
                           const CameraIntegrator& integrator, const RenderOptions& opt) {
    StageGraph graph;
    graph.set_progress(opt.progress);
    RenderResult result = render_camera(scene, settings, integrator, opt, graph, {});
    result.stats.graph = graph.report();
    return result;
}

RenderResult render_camera(const Scene& scene, const RenderSettings& settings,
                           const CameraIntegrator& integrator, const RenderOptions& opt,
                           StageGraph& graph, const std::vector<uint32_t>& after) {
    RenderResult result;
    PixelSums acc(scene.film.width, scene.film.height);
    acc.set_max_sample_value(scene.film.max_sample_value);
    if (settings.aovs & kAovVariance) acc.keep_moments();
    if (scene.film.filter.negative_lobes()) acc.use_weights();
    // The components AOV: a pixel sum per part of the integrator's estimate.
    const std::vector<std::string> part_names =
        settings.aovs & kAovComponents ? integrator.components() : std::vector<std::string>{};
    std::vector<PixelSums> parts(part_names.size(), PixelSums(scene.film.width, scene.film.height));
    if (scene.film.filter.negative_lobes())
        for (PixelSums& part : parts) part.use_weights();
    // Across MPI ranks the tiles are dealt out in turn (tile i to rank i mod N); each rank
    // renders its own, and rank 0 gathers their pixels when the image is needed.
    const Cluster& cluster = cluster_or_solo(opt.cluster);
    const std::vector<Tile> all_tiles =
        make_tiles(scene.film.width, scene.film.height, opt.tile_size);
    std::vector<Tile> tiles;
    if (cluster.distributed()) {
        PixelOwners owner(acc.size());
        for (std::size_t i = 0; i < all_tiles.size(); ++i) {
            const Tile& t = all_tiles[i];
            for (int y = t.y0; y < t.y1; ++y)
                for (int x = t.x0; x < t.x1; ++x)
                    owner[std::size_t(y) * std::size_t(scene.film.width) + std::size_t(x)] =
                        dealt_to(i, cluster.size());
        }
        for (PixelSums& p : parts) p.set_owners(owner);
        acc.set_owners(std::move(owner));
    }
    for (const uint64_t i : dealt_in_turn(all_tiles.size(), cluster)) tiles.push_back(all_tiles[i]);
    const CameraDriver driver(scene, opt);
    const int threads = resolve_threads(opt.threads);
    const bool adaptive = settings.adaptive.enabled;

    // The graph's tile nodes: the integrator's phases (one adaptive-sampling node instead,
    // whose rounds need the tile's own results), then accumulation.
    std::vector<uint32_t> nodes;
    if (adaptive) {
        nodes.push_back(graph.declare("adaptive-sampling"));
    } else {
        for (uint32_t p = 0; p < integrator.phases(); ++p)
            nodes.push_back(graph.declare(integrator.phase_name(p)));
    }
    nodes.push_back(graph.declare("accumulate"));
    for (uint32_t a : after) graph.edge(a, nodes.front());
    for (std::size_t i = 1; i < nodes.size(); ++i) graph.edge(nodes[i - 1], nodes[i]);

    // A tile in flight, with the workspace that carries its samples from node to node.
    struct TileWork {
        std::size_t tile = 0;
        std::unique_ptr<IntegratorWorkspace> ws;
        std::vector<SampleJob> jobs;
        std::vector<RGB> out;
        std::vector<float> weights;  // per job (a filter with negative lobes), else empty
        TileSums sums;
    };
    std::vector<std::unique_ptr<TileWork>> owned;
    tbb::concurrent_queue<TileWork*> idle;
    // Tiles in flight at once: enough to keep every thread busy, few enough to bound memory.
    const std::size_t in_flight = std::size_t(4 * threads);
    tbb::enumerable_thread_specific<RenderStats> stats;
    const ProgressTask* progress_task = nullptr;

    // A pass of many samples per pixel runs in pieces of at most opt.chunk_spp, one after
    // the other: a tile's jobs stay small, and as every pixel still adds its samples in
    // order, the image is the same bit for bit.
    const uint32_t chunk = adaptive ? opt.spp : std::max<uint32_t>(1, opt.chunk_spp);
    const uint32_t pieces = (opt.spp + chunk - 1) / chunk;
    auto run_piece = [&](uint32_t pass, uint32_t s0, uint32_t s1) {
        namespace flow = tbb::flow;
        flow::graph g;
        std::size_t next = 0;
        flow::input_node<TileWork*> source(g, [&](tbb::flow_control& fc) -> TileWork* {
            // A cancelled render hands out no further tile: the pass ends with what is done.
            if (next == tiles.size() || (opt.cancel && opt.cancel->load())) {
                fc.stop();
                return nullptr;
            }
            // The source holds one tile ahead of the limiter, so the pool may run dry once.
            TileWork* w = nullptr;
            if (!idle.try_pop(w)) {
                owned.push_back(std::make_unique<TileWork>());
                owned.back()->ws = integrator.make_workspace();
                owned.back()->ws->part_count = uint32_t(part_names.size());
                w = owned.back().get();
            }
            w->tile = next++;
            return w;
        });
        flow::limiter_node<TileWork*> limit(g, in_flight);
        std::vector<std::unique_ptr<flow::function_node<TileWork*, TileWork*>>> stages;
        for (std::size_t k = 0; k + 1 < nodes.size(); ++k) {
            stages.push_back(std::make_unique<flow::function_node<TileWork*, TileWork*>>(
                g, flow::unlimited, [&, k](TileWork* w) {
                    NodeTimer timer(graph, nodes[k]);
                    RenderStats& st = stats.local();
                    const Tile& t = tiles[w->tile];
                    if (adaptive) {
                        adaptive_tile(scene, settings.adaptive, settings.sampler, opt.seed,
                                      integrator, t, *w->ws, st, w->jobs, w->out, w->sums);
                    } else {
                        if (k == 0) {
                            driver.make_jobs(t, pass, s0, s1, w->jobs);
                            w->ws->parts.assign(w->jobs.size() * part_names.size(), RGB{0.f});
                        }
                        integrator.trace_phase(uint32_t(k), w->jobs, *w->ws, w->out, st);
                        // The last phase done: a filter with negative lobes weighs the samples.
                        if (k + 2 == nodes.size() &&
                            !camera_sample_weights(scene, settings.sampler, w->jobs, opt.seed,
                                                   w->weights))
                            w->weights.clear();
                    }
                    timer.items = w->jobs.size();
                    return w;
                }));
        }
        flow::function_node<TileWork*, flow::continue_msg> accumulate(
            g, flow::unlimited, [&](TileWork* w) {
                NodeTimer timer(graph, nodes.back());
                RenderStats& st = stats.local();
                if (adaptive)
                    driver.accumulate_tile(tiles[w->tile], w->sums, acc, parts, st);
                else
                    driver.accumulate_samples(w->jobs, w->out, w->weights, *w->ws, acc, parts, st);
                timer.items = tiles[w->tile].pixels();
                idle.push(w);
                progress_task->advance();
                return flow::continue_msg();
            });
        flow::make_edge(source, limit);
        flow::make_edge(limit, *stages.front());
        for (std::size_t k = 1; k < stages.size(); ++k) flow::make_edge(*stages[k - 1], *stages[k]);
        flow::make_edge(*stages.back(), accumulate);
        flow::make_edge(accumulate, limit.decrementer());
        source.activate();
        g.wait_for_all();
    };
    auto run_pass = [&](uint32_t pass) {
        for (uint32_t p = 0; p < pieces; ++p)
            run_piece(pass, p * chunk, std::min(opt.spp, (p + 1) * chunk));
    };

    PassControl control(opt);
    uint32_t passes = 0;
    {
        const ProgressTask task =
            control.task(adaptive ? "adaptive-sampling" : integrator.phase_name(0),
                         uint64_t(tiles.size()) * pieces);
        progress_task = &task;
        PinnedArena arena(threads);
        passes = control.run([&](uint32_t k) { arena.execute([&] { run_pass(k); }); },
                             [&] {
                                 acc.gather(cluster);
                                 return acc.mean();
                             },
                             [&] { return mean_count(acc.samples()); }, adaptive);
    }
    acc.gather(cluster);
    result.stats.wall_seconds = control.elapsed();
    for (const RenderStats& s : stats) result.stats.merge(s);
    result.stats.threads = threads;
    result.stats.passes = passes;
    result.film = acc.mean();
    result.samples_per_pixel = acc.samples();
    if (acc.keeps_moments()) result.aovs.push_back(acc.variance());
    for (std::size_t c = 0; c < parts.size(); ++c) {
        parts[c].gather(cluster);
        const Film f = parts[c].mean();
        const std::string& name = part_names[c];
        AovLayer layer{name, {name + ".R", name + ".G", name + ".B"}, {}};
        const float* rgb = reinterpret_cast<const float*>(f.pixels.data());
        layer.values.assign(rgb, rgb + 3 * f.pixels.size());
        result.aovs.push_back(std::move(layer));
    }
    return result;
}

}  // namespace foton
