#include "vcm_render.h"

#include <algorithm>
#include <cmath>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <tbb/task_arena.h>

#include "camera_subpaths.h"
#include "engine/core/error.h"
#include "engine/core/thread_pinning.h"
#include "engine/film/pixel_sums.h"
#include "engine/transport/common/medium_locate.h"
#include "engine/transport/run/pass_control.h"
#include "engine/transport/run/stage_graph.h"
#include "light_subpaths.h"

namespace foton {

namespace {

enum class BidirMode { Bdpt, Bpm, Vcm };

RenderResult render_bidir(BidirMode mode, const Scene& scene, const RenderSettings& settings,
                          const Intersector& accel, const RenderOptions& opt) {
    const char* name = mode == BidirMode::Bdpt ? "bdpt" : mode == BidirMode::Bpm ? "bpm" : "vcm";
    if (scene.camera.type != CameraType::Perspective)
        throw InputError(scene.source, 0,
                         std::string(name) +
                             " needs a perspective camera (a pinhole or a thin lens): light "
                             "subpaths are joined to the camera, and an orthographic camera "
                             "sees along one direction only");
    const LightSet lights(scene, LightSelection::Power, settings.projection_maps);
    if (lights.empty()) throw InputError(scene.source, 0, std::string(name) + " needs a light");

    // One light path per pixel of the whole image, also for a crop window: a camera path
    // meets the light path of its pixel's place in the image, so a crop renders exactly the
    // full render's pixels (as the light tracer traces the whole image's paths).
    const uint32_t pixels = uint32_t(scene.film.width) * uint32_t(scene.film.height);
    const uint64_t full = scene.film.full_pixels();
    if (full > uint64_t(1) << 31)
        throw InputError(scene.source, 0, std::string(name) + ": at most 2^31 pixels");
    const uint32_t paths = uint32_t(full);
    VcmContext ctx{scene, settings, accel,        lights,  opt.seed,        9, 0, 0, 0, 1,
                   0,     0.f,      VcmWeights{}, nullptr, StrategyLayers{}};
    ctx.max_segments = settings.max_depth + 1;
    ctx.light_paths = paths;
    ctx.weights.connect = mode != BidirMode::Bpm;
    ctx.weights.merge = mode != BidirMode::Bdpt;
    ctx.weights.beta = settings.mis == MisHeuristic::Balance ? 1.f : settings.mis_beta;
    ctx.weights.only_s = settings.bidir.only_s;
    ctx.weights.only_t = settings.bidir.only_t;
    // Media (bdpt and vcm; bpm merges at surfaces only, so a path whose only non-delta
    // vertices are in a medium would be missed, and the registry refuses it media).
    std::vector<int32_t> light_medium;
    if (scene.volumetric()) {
        refuse_emitting_media(scene, std::string(name) +
                                         " starts light paths at lights only: render it with "
                                         "volpath");
        light_medium = light_media(scene, accel, lights);
        ctx.media = true;
        ctx.light_medium = &light_medium;
    }
    KernelMaterials kernels = kernel_materials(scene);
    kernels.enabled = settings.simd_shading;
    ctx.kernels = &kernels;
    ctx.layers = {settings.bidir.strategy_images, mode != BidirMode::Bdpt};
    const uint32_t n_layers = ctx.layers.count();
    const float radius0 = settings.photon.initial_radius > 0.f ? settings.photon.initial_radius
                                                               : 0.005f * lights.scene_radius();
    const float alpha = settings.photon.alpha;

    const int threads = resolve_threads(opt.threads);
    constexpr uint32_t kLightChunk = 4096, kCameraChunk = 2048;
    const std::size_t light_chunks = (paths + kLightChunk - 1) / kLightChunk;
    const std::size_t camera_chunks = (pixels + kCameraChunk - 1) / kCameraChunk;
    // Across MPI ranks each traces a contiguous share of the light paths, and every rank gets
    // all their vertices (rank order is chunk order). Camera chunks are dealt out in turn;
    // a rank's pixel sums hold its own pixels only, and every rank adds the splats that land
    // on its pixels in chunk order, as one process adds them to each pixel.
    const Cluster& cluster = cluster_or_solo(opt.cluster);
    const Share light_mine = share_of(light_chunks, cluster);
    const std::vector<uint64_t> camera_mine = dealt_in_turn(camera_chunks, cluster);
    PixelSums sums(scene.film.width, scene.film.height);
    sums.set_max_sample_value(scene.film.max_sample_value);
    if (cluster.distributed()) sums.set_owners(owners_by_run(pixels, kCameraChunk, cluster.size()));
    std::vector<LightVertices> chunk_vertices(light_chunks);
    std::vector<std::vector<Splat>> splats(light_chunks);
    // strategy_images: a pixel sum per strategy layer, each splat's layer beside it.
    std::vector<PixelSums> layer_sums(n_layers, PixelSums(scene.film.width, scene.film.height));
    if (cluster.distributed())
        for (PixelSums& l : layer_sums) l.set_owners(sums.owners());
    std::vector<std::vector<uint32_t>> splat_layers(n_layers ? light_chunks : 0);
    LightPathStore store;
    store.use_kdtree = settings.bidir.merge_index == MergeIndex::KdTree;
    tbb::enumerable_thread_specific<LightSubpathWorkspace> light_ws;
    tbb::enumerable_thread_specific<CameraSubpathWorkspace> camera_ws;
    tbb::enumerable_thread_specific<RenderStats> stats;
    PassControl control(opt);
    const ProgressTask task = control.task(name, uint64_t(opt.spp) * camera_mine.size());
    uint64_t iterations = 0;

    StageGraph graph;
    graph.set_progress(opt.progress);
    const uint32_t light = graph.add("light-paths", [&]() -> uint64_t {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(light_mine.begin, light_mine.end, 1),
                          [&](const tbb::blocked_range<std::size_t>& r) {
                              LightSubpathWorkspace& ws = light_ws.local();
                              RenderStats& st = stats.local();
                              for (std::size_t k = r.begin(); k != r.end(); ++k) {
                                  const uint32_t first = uint32_t(k) * kLightChunk;
                                  const uint32_t n = std::min(kLightChunk, paths - first);
                                  chunk_vertices[k].clear();
                                  splats[k].clear();
                                  if (n_layers) splat_layers[k].clear();
                                  if (opt.cancel && opt.cancel->load(std::memory_order_relaxed))
                                      continue;  // a cancelled iteration traces no more
                                  trace_light_subpaths(ctx, first, n, ws, chunk_vertices[k],
                                                       splats[k],
                                                       n_layers ? &splat_layers[k] : nullptr, st);
                              }
                          });
        return std::min<uint64_t>(paths, light_mine.end * kLightChunk) -
               light_mine.begin * kLightChunk;
    });
    const uint32_t vertices = graph.add("light-vertices", [&]() -> uint64_t {
        StageClock clock;
        // This rank's chunks' vertices, in chunk order, copied in parallel (and every
        // rank's, across ranks); then where each path begins: the vertices are in path order.
        LightVertices& v = store.vertices;
        const std::size_t mine = light_mine.size();
        std::vector<std::size_t> at(mine + 1, 0);
        for (std::size_t k = 0; k < mine; ++k)
            at[k + 1] = at[k] + chunk_vertices[light_mine.begin + k].size();
        v.resize(at[mine]);
        tbb::parallel_for(std::size_t(0), mine, [&](std::size_t k) {
            v.copy_from(chunk_vertices[light_mine.begin + k], at[k]);
        });
        if (cluster.distributed()) v.all_gather(cluster);
        store.first.assign(std::size_t(paths) + 1, 0);
        tbb::parallel_for(std::size_t(0), light_chunks, [&](std::size_t k) {
            const uint32_t p0 = uint32_t(k) * kLightChunk, p1 = std::min(p0 + kLightChunk, paths);
            std::size_t i =
                std::size_t(std::lower_bound(v.path.begin(), v.path.end(), p0) - v.path.begin());
            for (uint32_t p = p0; p < p1; ++p) {
                store.first[p] = uint32_t(i);
                while (i < v.size() && v.path[i] == p) ++i;
            }
        });
        store.first[paths] = uint32_t(v.size());
        if (ctx.weights.merge) {
            store.radius = ctx.radius;
            if (store.use_kdtree)
                store.kdtree.build(
                    v.px.data(), v.py.data(), v.pz.data(), v.size(),
                    [](const std::function<void()>& a, const std::function<void()>& b) {
                        tbb::parallel_invoke(a, b);
                    });
            else
                store.grid.build(v, ctx.radius, settings.simd_shading);
        }
        stats.local().add(Stage::LightVertices, v.size(), clock);
        return v.size();
    });
    const uint32_t camera = graph.add("camera-paths", [&]() -> uint64_t {
        tbb::parallel_for(
            tbb::blocked_range<std::size_t>(0, camera_mine.size(), 1),
            [&](const tbb::blocked_range<std::size_t>& r) {
                CameraSubpathWorkspace& ws = camera_ws.local();
                RenderStats& st = stats.local();
                std::vector<RGB> radiance, by_layer;
                for (std::size_t j = r.begin(); j != r.end(); ++j) {
                    if (opt.cancel && opt.cancel->load(std::memory_order_relaxed)) break;
                    const std::size_t k = camera_mine[j];
                    const uint32_t first = uint32_t(k) * kCameraChunk;
                    const uint32_t n = std::min(kCameraChunk, pixels - first);
                    trace_camera_subpaths(ctx, store, first, n, ws, radiance, &by_layer, st);
                    for (uint32_t i = 0; i < n; ++i)
                        sums.add(first + i,
                                 clamp_max_component(radiance[i], scene.film.max_sample_value));
                    for (uint32_t i = 0; i < n; ++i)
                        for (uint32_t l = 0; l < n_layers; ++l)
                            layer_sums[l].add(first + i, by_layer[std::size_t(i) * n_layers + l]);
                    st.samples += n;
                    task.advance();
                }
            });
        uint64_t traced = 0;
        for (const uint64_t k : camera_mine)
            traced += std::min(kCameraChunk, pixels - uint32_t(k) * kCameraChunk);
        return traced;
    });
    const uint32_t splat = graph.add("splat", [&]() -> uint64_t {
        StageClock clock;
        const std::size_t count = sums.add_splats(splats, light_mine, cluster);
        // Each layer's splats, sorted out in one pass, in the same chunk order.
        if (n_layers) {
            std::vector<std::vector<std::vector<Splat>>> by_layer(
                n_layers, std::vector<std::vector<Splat>>(light_chunks));
            for (uint64_t k = light_mine.begin; k < light_mine.end; ++k)
                for (std::size_t i = 0; i < splats[k].size(); ++i)
                    by_layer[splat_layers[k][i]][k].push_back(splats[k][i]);
            for (uint32_t l = 0; l < n_layers; ++l)
                layer_sums[l].add_splats(by_layer[l], light_mine, cluster);
        }
        stats.local().add(Stage::Accumulate, count, clock);
        return count;
    });
    graph.edge(light, vertices);
    graph.edge(vertices, camera);
    graph.edge(light, splat);
    graph.edge(camera, splat);  // both add to `sums`

    // Collective across ranks: the image is whole on rank 0.
    auto image = [&] {
        sums.gather(cluster);
        return sums.scaled(iterations ? float(1.0 / double(iterations)) : 0.f);
    };
    PinnedArena arena(threads);
    uint32_t passes = 0;
    auto pass = [&](uint32_t k) {
        passes = k;
        for (uint32_t s = 0; s < opt.spp; ++s) {
            // The radius of iteration i (from 1): r0 i^((alpha - 1) / 2), so its area shrinks
            // as i^(alpha - 1) (Knaus and Zwicker's progressive photon mapping).
            ctx.iteration = iterations;
            ctx.pass = passes;
            ctx.pass_sample = s;
            ctx.pass_samples = opt.spp;
            ctx.radius = radius0 * std::pow(float(iterations + 1), 0.5f * (alpha - 1.f));
            const float eta = kPi * ctx.radius * ctx.radius * float(paths);
            VcmWeights& w = ctx.weights;
            w.vm_weight = w.merge ? w.mis(eta) : 0.f;
            w.vc_weight = w.connect ? w.mis(1.f / eta) : 0.f;
            w.vm_norm = w.merge ? 1.f / eta : 0.f;
            graph.run(arena);
            ++iterations;
        }
    };
    passes = control.run(pass, image, [&] { return double(iterations); });

    RenderResult result;
    result.stats.wall_seconds = control.elapsed();
    for (const RenderStats& s : stats) result.stats.merge(s);
    result.stats.threads = threads;
    result.stats.passes = passes;
    result.stats.graph = graph.report();
    result.film = image();
    result.samples_per_pixel.assign(sums.size(), uint32_t(iterations));
    for (uint32_t l = 0; l < n_layers; ++l) {
        layer_sums[l].gather(cluster);
        const Film f = layer_sums[l].scaled(iterations ? float(1.0 / double(iterations)) : 0.f);
        const std::string name = ctx.layers.name(l);
        AovLayer layer{name, {name + ".R", name + ".G", name + ".B"}, {}};
        const float* rgb = reinterpret_cast<const float*>(f.pixels.data());
        layer.values.assign(rgb, rgb + 3 * f.pixels.size());
        result.aovs.push_back(std::move(layer));
    }
    return result;
}

}  // namespace

RenderResult render_bdpt(const Scene& scene, const RenderSettings& settings,
                         const Intersector& accel, const RenderOptions& opt) {
    return render_bidir(BidirMode::Bdpt, scene, settings, accel, opt);
}
RenderResult render_bpm(const Scene& scene, const RenderSettings& settings,
                        const Intersector& accel, const RenderOptions& opt) {
    return render_bidir(BidirMode::Bpm, scene, settings, accel, opt);
}
RenderResult render_vcm(const Scene& scene, const RenderSettings& settings,
                        const Intersector& accel, const RenderOptions& opt) {
    return render_bidir(BidirMode::Vcm, scene, settings, accel, opt);
}

}  // namespace foton
