#include "photon_render.h"

#include <chrono>

#include <tbb/blocked_range.h>
#include <tbb/flow_graph.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <tbb/task_arena.h>

#include "engine/core/error.h"
#include "engine/scene/light_set.h"
#include "engine/transport/driver/camera_driver.h"
#include "engine/transport/irradiance_cache/cache_render.h"
#include "engine/transport/path/path.h"
#include "photon_integrator.h"
#include "photon_tracer.h"

namespace foton {

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
    StageClock photon_clock;
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
    const double photon_seconds = photon_clock.lap();
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
                                    PathIntegrator(scene, accel, lights, opt.seed, false), opt)
                              : render_camera(scene, integrator, opt);
    result.stats.merge(photon_stats);
    result.stats.wall_seconds += photon_seconds;
    result.stats.photons_global = maps.global.size() + maps.direct.size();
    result.stats.photons_caustic = maps.caustic.size();
    result.stats.photon_seconds = photon_seconds;
    return result;
}

}  // namespace foton
