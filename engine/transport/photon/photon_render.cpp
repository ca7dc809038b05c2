#include "photon_render.h"

#include <chrono>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "engine/core/error.h"
#include "engine/core/thread_pinning.h"
#include "engine/scene/light_set.h"
#include "engine/transport/irradiance_cache/cache_render.h"
#include "engine/transport/run/camera_driver.h"
#include "engine/transport/run/stage_graph.h"
#include "photon_integrator.h"
#include "photon_tracer.h"

namespace foton {

namespace {
// Whether any surface reflects or refracts through a delta lobe (a mirror, glass).
bool has_delta_lobe(const Scene& scene) {
    for (const Material& m : scene.materials)
        if (m.bsdf.has_delta()) return true;
    return false;
}
}  // namespace

RenderResult render_photon(const Scene& scene, const RenderSettings& settings,
                           const Intersector& accel, const RenderOptions& render_opt,
                           const PathOnwards& path_onwards) {
    // The camera passes' times (and a time budget) count the photon passes too.
    RenderOptions opt = render_opt;
    if (!opt.start) opt.start = RenderStart::now();
    const PhotonSettings& ps = settings.photon;
    const LightSet lights(scene, settings.light_selection, settings.projection_maps);
    if (lights.empty()) throw InputError(scene.source, 0, "photon mapping needs a light");
    const PhotonTracer tracer(scene, accel, lights, opt.seed);
    const float radius = 0.5f * length(scene.bounds().diagonal());
    PhotonMaps maps;
    EstimateParams& gp = maps.global_params;
    gp.k = ps.k;
    gp.max_radius = ps.max_radius > 0.f ? ps.max_radius : 0.05f * radius;
    gp.envelope = ps.envelope;
    gp.filter = ps.filter;
    gp.cone_k = ps.cone_k;
    EstimateParams& cp = maps.caustic_params;
    cp = gp;
    cp.k = ps.caustic_k;
    cp.max_radius = ps.caustic_radius > 0.f ? ps.caustic_radius : 0.02f * radius;
    cp.filter = ps.caustic_filter;

    // Visual importance (importons=N): where the camera looks, for final gathering one
    // bounce on too; built by the graph's first node, read by both photon passes.
    ImportonMap importance;
    RenderStats photon_stats, global_stats, caustic_stats;
    const int threads = resolve_threads(opt.threads);
    StageClock photon_clock;
    StageGraph graph;
    graph.set_progress(opt.progress);
    auto pass_settings = [&](PhotonMapKind kind, uint64_t emitted, uint64_t pass) {
        PhotonPassSettings s;
        s.kind = kind;
        s.emitted = emitted;
        s.max_depth = settings.max_depth;
        s.unscaled_roulette = ps.unscaled_roulette;
        s.pass = pass;
        s.cancel = opt.cancel;
        if (!importance.empty()) s.importance = &importance;
        return s;
    };
    const uint32_t trace_importons = graph.add("importons", [&]() -> uint64_t {
        if (ps.importons == 0) return 0;
        ImportonSettings is;
        is.count = ps.importons;
        is.diffuse_bounces = ps.mode == PhotonMode::FinalGather ? 1 : 0;
        is.max_specular = settings.max_depth;
        importance.build(scene, accel, is, opt.seed);
        return ps.importons;
    });
    const uint32_t trace_global = graph.add("photons-global", [&]() -> uint64_t {
        PhotonPassSettings s = pass_settings(PhotonMapKind::Global, ps.global_photons, 0);
        s.shadow_photons = ps.shadow_photons;
        const ProgressTask task(graph.progress(), "photons-global", s.emitted);
        if (s.emitted > 0)
            maps.global = tracer.run(s, global_stats, &maps.shadow, &task, opt.cluster);
        if (ps.split_direct) {
            maps.direct = maps.global.extract(kPhotonDirect);
        } else if (ps.mode == PhotonMode::DirectVisualisation &&
                   settings.lighting != Lighting::All) {
            // Seen directly, the map is the light: keep the photons of the kind asked for.
            PhotonMap direct = maps.global.extract(kPhotonDirect);
            if (settings.lighting == Lighting::Direct) maps.global = std::move(direct);
        }
        if (ps.compact_power) {
            maps.global.compact_power();
            maps.direct.compact_power();
            maps.shadow.compact_power();
        }
        return s.emitted;
    });
    const uint32_t trace_caustic = graph.add("photons-caustic", [&]() -> uint64_t {
        const PhotonPassSettings s = pass_settings(PhotonMapKind::Caustic, ps.caustic_photons, 1);
        // The direct-visualisation mode reads the global map only; a scene without a mirror or
        // glass has no caustic photon to find (they arrive through delta lobes only).
        if (s.emitted == 0 || ps.mode != PhotonMode::FinalGather || !has_delta_lobe(scene))
            return 0;
        const ProgressTask task(graph.progress(), "photons-caustic", s.emitted);
        maps.caustic = tracer.run(s, caustic_stats, nullptr, &task, opt.cluster);
        if (ps.compact_power) maps.caustic.compact_power();
        return s.emitted;
    });
    // After a cancel the maps are neither balanced nor read: the camera pass starts no tile.
    // (Across ranks the balance and precomputation are collective: every rank runs them.)
    auto cancelled = [&] {
        return opt.cancel && opt.cancel->load() && !(opt.cluster && opt.cluster->distributed());
    };
    const uint32_t balance_global = graph.add("balance-global", [&]() -> uint64_t {
        if (cancelled()) return 0;
        StageClock c;
        const kern::PointKdTree::ParallelInvoke par =
            timed_parallel_invoke(ThreadClock::for_chunks());
        maps.global.build(par);
        maps.direct.build(par);
        maps.shadow.build(par);
        const uint64_t n = maps.global.size() + maps.direct.size() + maps.shadow.size();
        global_stats.add_wall(Stage::Balance, n, c);
        return n;
    });
    const uint32_t precompute = graph.add("precompute-irradiance", [&]() -> uint64_t {
        if (ps.mode != PhotonMode::FinalGather || ps.irradiance_stride == 0 || cancelled())
            return 0;
        StageClock c;
        BusyTime* const busy = ThreadClock::for_chunks();
        const auto parallel_for = [&](std::size_t n,
                                      const std::function<void(std::size_t, std::size_t)>& body) {
            const ProgressTask task(graph.progress(), "precompute-irradiance", n);
            tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1024),
                              [&](const tbb::blocked_range<std::size_t>& r) {
                                  const ThreadClock clock(busy);
                                  body(r.begin(), r.end());
                                  task.advance(r.size());
                              });
        };
        maps.global.precompute_irradiance(ps.irradiance_stride, gp, parallel_for, opt.cluster);
        if (!maps.direct.empty())
            maps.direct.precompute_irradiance(ps.irradiance_stride, gp, parallel_for, opt.cluster);
        const uint64_t n = maps.global.precomputed_size() + maps.direct.precomputed_size();
        global_stats.add_wall(Stage::Precompute, n, c);
        return n;
    });
    const uint32_t balance_caustic = graph.add("balance-caustic", [&]() -> uint64_t {
        if (cancelled()) return 0;
        StageClock c;
        maps.caustic.build(timed_parallel_invoke(ThreadClock::for_chunks()));
        caustic_stats.add_wall(Stage::Balance, maps.caustic.size(), c);
        return maps.caustic.size();
    });
    // Across MPI ranks the map exchanges (and the precomputed irradiance's) are collectives,
    // which every rank must run in the same order: those nodes then follow each other.
    if (opt.cluster && opt.cluster->distributed()) {
        graph.edge(trace_global, trace_caustic);
        graph.edge(trace_caustic, precompute);
    }
    graph.edge(trace_importons, trace_global);
    graph.edge(trace_importons, trace_caustic);
    graph.edge(trace_global, balance_global);
    graph.edge(trace_caustic, balance_caustic);
    graph.edge(balance_global, precompute);
    {
        PinnedArena arena(threads);
        graph.run(arena);
    }
    const double photon_seconds = photon_clock.lap();
    photon_stats.merge(global_stats);
    photon_stats.merge(caustic_stats);

    const RenderContext ctx{scene, settings, accel, lights, opt.seed};
    // The camera nodes (camera gather, final gather, accumulate; the cache fill before them)
    // join the graph after the maps are ready.
    const std::vector<uint32_t> maps_ready = graph.sinks();
    RenderResult result;
    if (settings.indirect == IndirectMode::IrradianceCache) {
        // The records' rays read the photons through an integrator that has no cache.
        const PhotonIntegrator photons(ctx, maps);
        const std::unique_ptr<RadianceAlongRays> onwards =
            path_onwards ? path_onwards(ctx) : nullptr;
        CacheClient client;
        client.camera = [&](const CacheEvaluator& cache) -> std::unique_ptr<CameraIntegrator> {
            return std::make_unique<PhotonIntegrator>(ctx, maps, &cache);
        };
        client.photons = [&](const SurfacePoint& sp, const Material& m, const Vec3& d) {
            return photons.photon_radiance(sp, m, d);
        };
        client.onwards = onwards.get();
        result = render_with_cache(ctx, client, opt, graph, maps_ready);
    } else {
        result =
            render_camera(scene, settings, PhotonIntegrator(ctx, maps), opt, graph, maps_ready);
    }
    result.stats.graph = graph.report();
    result.stats.merge(photon_stats);
    result.stats.photons_global = maps.global.size() + maps.direct.size();
    result.stats.photons_caustic = maps.caustic.size();
    result.stats.photon_seconds = photon_seconds;
    return result;
}

}  // namespace foton
