#include "render.h"

#include <tbb/info.h>

#include "engine/core/error.h"

namespace foton {

int resolve_threads(int requested) {
    return requested > 0 ? requested : tbb::info::default_concurrency();
}

RenderResult render(const Scene& scene, const RenderSettings& settings, const Intersector& accel,
                    const RenderOptions& opt) {
    const IntegratorInfo* info = find_integrator(settings.integrator);
    if (!info)
        throw InputError(
            scene.source, 0,
            "unknown renderer type '" + settings.integrator + "' (" + integrator_list() + ")");
    if (settings.indirect == IndirectMode::IrradianceCache && !info->irradiance_cache) {
        std::string which;
        for (const IntegratorInfo& i : integrators())
            if (i.irradiance_cache)
                which += std::string(which.empty() ? "" : " or ") + "type=\"" + i.name + "\"";
        throw InputError(
            "renderer", 0,
            "indirect=\"irradiance_cache\" needs " + which + " (photon in final-gather mode)");
    }
    return info->render(scene, settings, accel, opt);
}

RenderResult render(const Scene& scene, const Intersector& accel, const RenderOptions& opt) {
    return render(scene, render_settings(scene), accel, opt);
}

}  // namespace foton
