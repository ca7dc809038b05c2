#include "render.h"

#include <tbb/info.h>

#include "camera_driver.h"
#include "engine/core/error.h"
#include "engine/scene/light_set.h"
#include "engine/transport/irradiance_cache/cache_render.h"
#include "engine/transport/light/light_render.h"
#include "engine/transport/path/path.h"
#include "engine/transport/photon/photon_render.h"
#include "engine/transport/photon/sppm.h"
#include "engine/transport/whitted/whitted.h"

namespace foton {

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
                    [&](const CacheEvaluator* e) { integrator.set_cache(e); }, nullptr,
                    PathIntegrator(scene, accel, lights, opt.seed, false), opt);
            return render_camera(scene, integrator, opt);
        }
        case IntegratorType::Whitted:
            break;
    }
    const WhittedIntegrator integrator(scene, accel, opt.seed);
    return render_camera(scene, integrator, opt);
}

}  // namespace foton
