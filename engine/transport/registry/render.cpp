#include "render.h"

#include <algorithm>
#include <any>
#include <iterator>
#include <memory>

#include <tbb/global_control.h>
#include <tbb/info.h>

#include "engine/core/error.h"
#include "engine/transport/run/first_hit_aovs.h"
#include "engine/transport/volume/volpath.h"

namespace foton {

RenderResult render(const Scene& scene, const RenderSettings& settings, const Intersector& accel,
                    const RenderOptions& opt) {
    const IntegratorInfo* info = find_integrator(settings.integrator);
    if (!info)
        throw InputError(
            scene.source, 0,
            "unknown renderer type '" + settings.integrator + "' (" + integrator_list() + ")");
    // Settings made by hand (a test, a tool) meet the rules render_settings() checks.
    if (const std::optional<SettingsProblem> p = capability_problem(*info, settings))
        throw InputError("renderer", 0, p->key + (": " + p->message));
    // A scene with media rendered by an integrator that would pass through them silently.
    if (scene.volumetric() && !info->has(kCapMedia))
        throw InputError(scene.volumetric_file, scene.volumetric_line,
                         "the scene has participating media, which type=\"" +
                             std::string(info->name) + "\" does not trace: use " +
                             integrators_with(kCapMedia));
    // Subsurface materials would be glass to an integrator that does not follow light under
    // surfaces.
    if (!scene.subsurface_file.empty() && !info->has(kCapSubsurface))
        throw InputError(scene.subsurface_file, scene.subsurface_line,
                         "the scene has subsurface materials, which type=\"" +
                             std::string(info->name) + "\" does not follow under surfaces: use " +
                             integrators_with(kCapSubsurface));
    // A portal's light depends on where it is seen from; the bidirectional integrators'
    // weights read one density for an escaping camera ray and an emitted one.
    if (scene.environment && scene.environment->has_portal() && info->has(kCapBidirectional))
        throw InputError(scene.source, 0,
                         "the scene's environment light has a portal, which type=\"" +
                             std::string(info->name) +
                             "\" does not weigh: use the path tracers, the light tracer or "
                             "photon mapping");
    // oneTBB runs no more threads than the hardware has unless told otherwise: a request
    // for more (a scaling study, a determinism test) raises the limit for this render, so
    // the threads recorded are the threads that ran.
    std::unique_ptr<tbb::global_control> allow;
    if (opt.threads > kMaxThreads)
        throw InputError("threads", 0,
                         std::to_string(opt.threads) + " threads: at most " +
                             std::to_string(kMaxThreads) + " run");
    if (opt.threads > tbb::info::default_concurrency())
        allow = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                      std::size_t(opt.threads));
    RenderResult result = info->render(scene, settings, accel, opt);
    // The first-hit AOVs, on the rank that writes the image, before the ones the render made
    // (aov.h's order).
    if ((settings.aovs & kAovFirstHit) && cluster_or_solo(opt.cluster).root()) {
        std::vector<AovLayer> layers = render_first_hit_aovs(scene, settings, accel, opt);
        layers.insert(layers.end(), std::make_move_iterator(result.aovs.begin()),
                      std::make_move_iterator(result.aovs.end()));
        result.aovs = std::move(layers);
    }
    return result;
}

RenderResult render(const Scene& scene, const Intersector& accel, const RenderOptions& opt) {
    return render(scene, render_settings(scene), accel, opt);
}

std::string integrator_label(const RenderSettings& settings) {
    const VolPathSettings* own = std::any_cast<VolPathSettings>(&settings.own);
    return settings.integrator + (own && own->spectral ? " (spectral)" : "");
}

}  // namespace foton
