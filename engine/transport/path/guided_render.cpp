#include <tbb/task_arena.h>

#include "engine/core/error.h"
#include "engine/core/thread_pinning.h"
#include "engine/transport/photon/photon_tracer.h"
#include "engine/transport/run/camera_driver.h"
#include "engine/transport/run/stage_graph.h"
#include "path.h"
#include "path_guide.h"

namespace foton {

RenderResult render_guided_path(const RenderContext& ctx, const RenderOptions& render_opt) {
    const Scene& scene = ctx.scene;
    const RenderSettings& settings = ctx.settings;
    // The camera passes' times (and a time budget) count the guide's pre-pass too.
    RenderOptions opt = render_opt;
    if (!opt.start) opt.start = RenderStart::now();
    if (ctx.lights.empty()) throw InputError(scene.source, 0, "guided paths need a light");
    const PathGuideSettings& gs = settings.guide;
    const PhotonTracer tracer(scene, ctx.accel, ctx.lights, opt.seed);

    PhotonMap photons;
    PathGuide guide;
    RenderStats stats;
    StageGraph graph;
    graph.set_progress(opt.progress);
    const uint32_t trace = graph.add("photons-guide", [&]() -> uint64_t {
        PhotonPassSettings s;
        s.kind = PhotonMapKind::Global;
        s.emitted = gs.emitted;
        s.max_depth = settings.max_depth;
        s.cancel = opt.cancel;
        const ProgressTask task(graph.progress(), "photons-guide", s.emitted);
        photons = tracer.run(s, stats, nullptr, &task, opt.cluster);
        if (settings.photon.compact_power) photons.compact_power();
        return s.emitted;
    });
    const uint32_t build = graph.add("build-guide", [&]() -> uint64_t {
        StageClock c;
        // Next event estimation finds the lights; without it the direct photons guide too.
        const uint8_t flags = uint8_t(kPhotonViaSpecular | (settings.nee ? 0 : kPhotonDirect));
        guide.build(photons, flags, scene.bounds(), gs);
        stats.add(Stage::GuideBins, photons.size(), c);
        return guide.size();
    });
    graph.edge(trace, build);
    {
        PinnedArena arena(resolve_threads(opt.threads));
        graph.run(arena);
    }
    const PathIntegrator integrator(ctx, VertexRules::path(settings), PathReaders{nullptr, &guide});
    RenderResult result = render_camera(scene, settings, integrator, opt, graph, graph.sinks());
    result.stats.graph = graph.report();
    result.stats.merge(stats);
    result.stats.photons_global = photons.size();
    return result;
}

}  // namespace foton
