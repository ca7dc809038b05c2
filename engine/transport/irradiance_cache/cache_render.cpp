#include "cache_render.h"

#include <chrono>
#include <stdexcept>

#include "cache_fill.h"
#include "engine/core/error.h"
#include "engine/transport/run/camera_driver.h"

namespace foton {

CacheSecondary cache_secondary(const CacheSettings& settings, bool photon_map) {
    const CacheSecondary m = settings.secondary;
    if (m == CacheSecondary::Auto)
        return photon_map ? CacheSecondary::Photon : CacheSecondary::Path;
    // The settings refuse this (capability_problem, registry/integrators.cpp, at the key's
    // file and line); reaching it is a caller's bug, not bad input.
    if (m == CacheSecondary::Photon && !photon_map)
        throw std::logic_error("cache_secondary=\"photon\" without a photon map");
    return m;
}

// One cache per level, filled in hierarchical passes, then read (frozen) by the image pass.
RenderResult render_with_cache(const Scene& scene, const RenderSettings& settings,
                               const Intersector& accel, const LightSet& lights,
                               const CameraIntegrator& integrator,
                               const std::function<void(const CacheEvaluator*)>& attach,
                               CacheEvaluator::PhotonRadiance photons,
                               const RadianceAlongRays& onwards, const RenderOptions& opt,
                               StageGraph& graph, const std::vector<uint32_t>& after) {
    // The passes' times (and a time budget) count the fill too.
    RenderOptions pass_opt = opt;
    if (!pass_opt.start) pass_opt.start = RenderStart::now();
    const CacheSecondary secondary = cache_secondary(settings.cache, bool(photons));
    CacheEvaluator evaluator(scene, settings, accel, lights, opt.seed, secondary,
                             std::move(photons), &onwards);
    std::vector<IrradianceCache> caches(evaluator.levels(),
                                        IrradianceCache(scene.bounds(), evaluator.params()));
    std::vector<const IrradianceCache*> frozen;
    for (const IrradianceCache& c : caches) frozen.push_back(&c);
    evaluator.set_caches(frozen);
    attach(&evaluator);
    RenderStats fill_stats;
    StageClock fill_clock;
    const uint32_t fill =
        fill_irradiance_cache(scene, integrator, caches, opt.spp, resolve_threads(opt.threads),
                              fill_stats, graph, after, opt.cluster);
    const double fill_seconds = fill_clock.lap();
    std::size_t stored = 0;
    for (const IrradianceCache& c : caches) stored += c.size();
    RenderResult result = render_camera(scene, settings, integrator, pass_opt, graph, {fill});
    attach(nullptr);
    result.stats.merge(fill_stats);
    result.stats.cache_fill_seconds = fill_seconds;
    result.stats.cache_stored = stored;
    for (std::size_t i = 0; i < caches[0].size(); ++i)
        result.cache_points.push_back(caches[0].record(i).p);
    return result;
}

}  // namespace foton
