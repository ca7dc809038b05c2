#include "light_render.h"

#include <algorithm>
#include <atomic>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "engine/core/error.h"
#include "engine/core/thread_pinning.h"
#include "engine/film/pixel_sums.h"
#include "engine/scene/light_set.h"
#include "engine/transport/common/medium_locate.h"
#include "engine/transport/run/pass_control.h"
#include "engine/transport/run/stage_graph.h"
#include "engine/transport/volume/volume_light.h"
#include "light_tracer.h"

namespace foton {

namespace {

// Light paths in passes of chunks, their splats added in chunk order: Workspace is the
// tracer's (the light tracer's, or the volumetric one's when the scene has media).
template <class Workspace, class Tracer>
RenderResult render_light_paths(const Scene& scene, const Tracer& tracer,
                                const RenderOptions& opt) {
    const int threads = resolve_threads(opt.threads);
    const uint64_t per_pass = scene.film.full_pixels() * uint64_t(opt.spp);
    constexpr uint32_t kChunk = 4096;
    const std::size_t chunks = std::size_t((per_pass + kChunk - 1) / kChunk);
    // Across MPI ranks each traces a contiguous share of every pass's chunks; rank 0 adds
    // the splats of all in rank order, which is chunk order.
    const Cluster& cluster = cluster_or_solo(opt.cluster);
    const Share mine = share_of(chunks, cluster);
    // Rank 0 adds every splat (no owners): its sums are the image.
    PixelSums sums(scene.film.width, scene.film.height);
    sums.set_max_sample_value(scene.film.max_sample_value);
    std::vector<std::vector<Splat>> splats(chunks);
    tbb::enumerable_thread_specific<Workspace> workspaces;
    tbb::enumerable_thread_specific<RenderStats> stats;
    PassControl control(opt);
    const ProgressTask task = control.task("light-paths", mine.size());
    uint32_t passes = 0;
    // A pixel's estimate is its splat sum over the number of paths traced: every pass's
    // per_pass, or fewer when a cancelled pass stopped early (in one process; across ranks
    // each rank counts only its own share, so the passes' count stands).
    std::atomic<uint64_t> traced{0};
    auto image = [&] {
        const double paths = cluster.distributed() ? double(per_pass) * passes : double(traced);
        return sums.scaled(paths > 0.0 ? float(1.0 / paths) : 0.f);
    };
    // Per pass: the light paths in parallel chunks, then their splats in chunk order.
    StageGraph graph;
    graph.set_progress(opt.progress);
    const uint32_t trace = graph.add("light-paths", [&]() -> uint64_t {
        const uint64_t base = uint64_t(passes) * per_pass;
        tbb::parallel_for(tbb::blocked_range<std::size_t>(mine.begin, mine.end, 1),
                          [&](const tbb::blocked_range<std::size_t>& r) {
                              Workspace& ws = workspaces.local();
                              RenderStats& st = stats.local();
                              for (std::size_t c = r.begin(); c != r.end(); ++c) {
                                  splats[c].clear();
                                  if (opt.cancel && opt.cancel->load(std::memory_order_relaxed))
                                      continue;  // a cancelled pass traces no further chunk
                                  const uint64_t first = uint64_t(c) * kChunk;
                                  const uint32_t n =
                                      uint32_t(std::min<uint64_t>(kChunk, per_pass - first));
                                  tracer.trace(base + first, n, ws, splats[c], st);
                                  traced += n;
                                  task.advance();
                              }
                          });
        return uint64_t(std::min<uint64_t>(per_pass, mine.end * kChunk) - mine.begin * kChunk);
    });
    const uint32_t splat = graph.add("splat", [&]() -> uint64_t {
        StageClock clock;
        const std::size_t count = sums.add_splats(splats, mine, cluster);
        stats.local().add(Stage::Accumulate, count, clock);
        return count;
    });
    graph.edge(trace, splat);
    PinnedArena arena(threads);
    passes = control.run(
        [&](uint32_t k) {
            passes = k;  // the trace node keys the pass's paths by it
            graph.run(arena);
            passes = k + 1;
        },
        image, [&] { return double(opt.spp) * passes; });
    RenderResult result;
    result.stats.wall_seconds = control.elapsed();
    for (const RenderStats& s : stats) result.stats.merge(s);
    result.stats.threads = threads;
    result.stats.passes = passes;
    result.stats.graph = graph.report();
    result.film = image();
    result.samples_per_pixel.assign(sums.size(), opt.spp * passes);
    return result;
}

}  // namespace

RenderResult render_light(const Scene& scene, const RenderSettings& settings,
                          const Intersector& accel, const RenderOptions& opt) {
    if (scene.camera.type != CameraType::Perspective || scene.camera.lens_radius > 0.f)
        throw InputError(scene.source, 0,
                         "the light tracer needs a pinhole perspective camera (no lens_radius)");
    const LightSet lights(scene, LightSelection::Power, settings.projection_maps);
    if (lights.empty()) throw InputError(scene.source, 0, "the light tracer needs a light");
    const RenderContext ctx{scene, settings, accel, lights, opt.seed};
    if (scene.media.empty())
        return render_light_paths<LightTracerWorkspace>(scene, LightTracer(ctx), opt);
    refuse_emitting_media(scene, "light paths start at lights only: render it with volpath");
    return render_light_paths<VolumeLightWorkspace>(scene, VolumeLightTracer(ctx), opt);
}

}  // namespace foton
