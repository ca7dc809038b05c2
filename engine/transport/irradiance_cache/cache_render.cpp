#include "cache_render.h"

#include <chrono>
#include <stdexcept>

#include "cache_fill.h"
#include "engine/core/error.h"
#include "engine/transport/run/camera_driver.h"

namespace foton {

CacheSecondary cache_secondary(const CacheSettings& settings, bool photon_map, bool onwards) {
    const CacheSecondary m = settings.secondary;
    if (m == CacheSecondary::Auto)
        return photon_map ? CacheSecondary::Photon : CacheSecondary::Path;
    // The settings refuse this (capability_problem, registry/integrators.cpp, at the key's
    // file and line); reaching it is a caller's bug, not bad input.
    if (m == CacheSecondary::Photon && !photon_map)
        throw std::logic_error("cache_secondary=\"photon\" without a photon map");
    if (m == CacheSecondary::Path && !onwards)
        throw std::logic_error("cache_secondary=\"path\" without a path tracer to trace on");
    return m;
}

// One cache per level, filled in hierarchical passes, then read (frozen) by the image pass.
RenderResult render_with_cache(const RenderContext& ctx, const CacheClient& client,
                               const RenderOptions& opt, StageGraph& graph,
                               const std::vector<uint32_t>& after) {
    // The passes' times (and a time budget) count the fill too.
    RenderOptions pass_opt = opt;
    if (!pass_opt.start) pass_opt.start = RenderStart::now();
    const CacheSecondary secondary =
        cache_secondary(ctx.settings.cache, bool(client.photons), client.onwards != nullptr);
    CacheEvaluator evaluator(ctx, secondary, client.photons, client.onwards);
    std::vector<IrradianceCache> caches(evaluator.levels(),
                                        IrradianceCache(ctx.scene.bounds(), evaluator.params()));
    std::vector<const IrradianceCache*> frozen;
    for (const IrradianceCache& c : caches) frozen.push_back(&c);
    evaluator.set_caches(frozen);
    const std::unique_ptr<CameraIntegrator> integrator = client.camera(evaluator);
    RenderStats fill_stats;
    StageClock fill_clock;
    const uint32_t fill =
        fill_irradiance_cache(ctx.scene, *integrator, caches, opt.spp, resolve_threads(opt.threads),
                              fill_stats, graph, after, opt.cluster, opt.cancel);
    const double fill_seconds = fill_clock.lap();
    std::size_t stored = 0;
    for (const IrradianceCache& c : caches) stored += c.size();
    RenderResult result =
        render_camera(ctx.scene, ctx.settings, *integrator, pass_opt, graph, {fill});
    result.stats.merge(fill_stats);
    result.stats.cache_fill_seconds = fill_seconds;
    result.stats.cache_stored = stored;
    for (std::size_t i = 0; i < caches[0].size(); ++i)
        result.cache_points.push_back(caches[0].record(i).p);
    return result;
}

}  // namespace foton
