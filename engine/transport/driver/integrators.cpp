#include "integrators.h"

#include "engine/transport/bidir/vcm_render.h"
#include "engine/transport/light/light_render.h"
#include "engine/transport/path/path.h"
#include "engine/transport/photon/photon_render.h"
#include "engine/transport/photon/sppm.h"
#include "engine/transport/whitted/whitted.h"

namespace foton {

const std::vector<IntegratorInfo>& integrators() {
    // Every integrator splits its work across MPI ranks (RenderOptions::cluster).
    //                          name  aliases  camera  cache  render
    static const std::vector<IntegratorInfo> table = {
        {"raytracer", {"whitted"}, true, false, render_whitted},
        {"path", {}, true, true, render_path},
        {"distributed", {}, true, false, render_distributed},
        {"light", {}, false, false, render_light},
        {"photon", {}, true, true, render_photon},
        {"sppm", {}, false, false, render_sppm},
        {"ppm", {}, false, false, render_ppm},
        {"bdpt", {}, false, false, render_bdpt},
        {"bpm", {}, false, false, render_bpm},
        {"vcm", {}, false, false, render_vcm},
    };
    return table;
}

const IntegratorInfo* find_integrator(const std::string& name) {
    for (const IntegratorInfo& i : integrators()) {
        if (name == i.name) return &i;
        for (const char* a : i.aliases)
            if (name == a) return &i;
    }
    return nullptr;
}

std::string integrator_list() {
    std::string s;
    for (const IntegratorInfo& i : integrators())
        s += (s.empty() ? "" : ", ") + std::string(i.name);
    return s;
}

RenderSettings render_settings(const ParamSet& params) {
    RenderSettings r = parse_render_settings(params);
    const IntegratorInfo* info = find_integrator(r.integrator);
    if (!info)
        params.fail("type",
                    "unknown renderer type '" + r.integrator + "' (" + integrator_list() + ")");
    r.integrator = info->name;  // an alias becomes the name
    return r;
}

}  // namespace foton
