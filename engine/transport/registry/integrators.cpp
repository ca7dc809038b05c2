#include "integrators.h"

#include <algorithm>

#include "engine/core/error.h"

#include "engine/transport/ao/ao.h"
#include "engine/transport/bidir/vcm_render.h"
#include "engine/transport/light/light_render.h"
#include "engine/transport/mlt/mlt.h"
#include "engine/transport/path/path.h"
#include "engine/transport/photon/photon_render.h"
#include "engine/transport/photon/sppm.h"
#include "engine/transport/volume/volpath.h"
#include "engine/transport/volume/vpm.h"
#include "engine/transport/whitted/whitted.h"

namespace foton {

namespace {
// Photon mapping's irradiance cache traces on (cache_secondary="path") with the path family's
// tracer: the table is where the families meet.
RenderResult render_photon_row(const Scene& scene, const RenderSettings& settings,
                               const Intersector& accel, const RenderOptions& options) {
    return render_photon(scene, settings, accel, options, make_path_onwards);
}
}  // namespace

const std::vector<IntegratorInfo>& integrators() {
    // Every integrator splits its work across MPI ranks (RenderOptions::cluster).
    constexpr uint32_t kPath =
        kCapCamera | kCapIrradianceCache | kCapLightingSplit | kCapPhotonGuide | kCapLightSelection;
    constexpr uint32_t kPhoton = kCapCamera | kCapIrradianceCache | kCapLightingSplit |
                                 kCapPhotonMap | kCapLightSelection | kCapComponents;
    // One row per integrator: name, aliases, summary, capabilities, own parse, render.
    // clang-format off
    static const std::vector<IntegratorInfo> table = {
        {"raytracer", {"whitted"}, "Whitted ray tracing (the first thesis)", kCapCamera, nullptr, render_whitted},
        {"path", {}, "path tracing, NEE + MIS", kPath | kCapRegularize, nullptr, render_path},
        {"distributed", {}, "distributed ray tracing (Cook 1984)", kCapCamera, nullptr, render_distributed},
        {"light", {}, "light tracing (through media too)", kCapMedia, nullptr, render_light},
        {"photon", {}, "photon mapping: final gather, irradiance cache or direct visualisation", kPhoton, nullptr, render_photon_row},
        {"sppm", {}, "stochastic progressive photon mapping", kCapLightSelection, nullptr, render_sppm},
        {"ppm", {}, "progressive photon mapping", kCapLightSelection, nullptr, render_ppm},
        {"bdpt", {}, "bidirectional path tracing (through media too)", kCapBidirectional | kCapStrategyDebug | kCapMedia, nullptr, render_bdpt},
        {"bpm", {}, "bidirectional photon mapping", kCapBidirectional | kCapMerging, nullptr, render_bpm},
        {"vcm", {}, "vertex connection and merging (media: connections; merges at surfaces)", kCapBidirectional | kCapMerging | kCapMedia, nullptr, render_vcm},
        {"volpath", {}, "volumetric path tracing: participating media, NEE + MIS", kCapCamera | kCapLightSelection | kCapMedia | kCapSubsurface | kCapRegularize, parse_volpath, render_volpath},
        {"vpm", {"volumetric_photons"}, "volumetric photon mapping, progressive (media)", kCapLightSelection | kCapMedia, parse_vpm, render_vpm},
        {"ao", {"ambientocclusion"}, "ambient occlusion (ao_samples, ao_distance)", kCapCamera, parse_ao, render_ao},
        {"mlt", {"pssmlt"}, "Metropolis light transport in primary sample space (Kelemen 2002) over the path tracer", kCapLightSelection, parse_mlt, render_mlt},
    };
    // clang-format on
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

std::string integrator_list(const char* separator) {
    std::string s;
    for (const IntegratorInfo& i : integrators())
        s += (s.empty() ? "" : separator) + std::string(i.name);
    return s;
}

std::string integrator_help() {
    std::string s;
    for (const IntegratorInfo& i : integrators()) {
        s += "\n  " + std::string(i.name);
        for (const char* a : i.aliases) s += std::string(" (") + a + ")";
        s += ": " + std::string(i.summary);
    }
    return s;
}

std::string integrators_with(uint32_t caps) {
    std::vector<std::string> names;
    for (const IntegratorInfo& i : integrators())
        if (i.has(caps)) names.push_back(i.name);
    if (names.empty()) return "an integrator that has none here";
    std::string s = "type=\"" + names[0] + "\"";
    for (std::size_t k = 1; k < names.size(); ++k)
        s += std::string(k + 1 == names.size() ? " or " : ", ") + "\"" + names[k] + "\"";
    return s;
}

std::optional<SettingsProblem> capability_problem(const IntegratorInfo& info,
                                                  const RenderSettings& s) {
    if (s.adaptive.enabled && !info.has(kCapCamera))
        return SettingsProblem{"adaptive", "adaptive sampling applies to camera integrators (" +
                                               integrators_with(kCapCamera) + "), not type=\"" +
                                               info.name + "\""};
    for (const AovRequirement& q : kAovRequirements)
        if ((s.aovs & q.aov) && !info.has(q.cap))
            return SettingsProblem{"aov", std::string(q.needs) + " " + integrators_with(q.cap) +
                                              ", not type=\"" + info.name + "\""};
    if (s.indirect == IndirectMode::IrradianceCache) {
        if (!info.has(kCapIrradianceCache))
            return SettingsProblem{"indirect", "indirect=\"irradiance_cache\" needs " +
                                                   integrators_with(kCapIrradianceCache)};
        if (s.photon.mode != PhotonMode::FinalGather)
            return SettingsProblem{"indirect",
                                   "indirect=\"irradiance_cache\" needs photon mapping in "
                                   "final-gather mode (mode=\"final_gather\")"};
    }
    if (s.cache.secondary == CacheSecondary::Photon && !info.has(kCapPhotonMap))
        return SettingsProblem{"cache_secondary", "cache_secondary=\"photon\" needs " +
                                                      integrators_with(kCapPhotonMap) +
                                                      " (there is no photon map)"};
    return std::nullopt;
}

namespace {

// Settings that only other integrators take, in a scene written for one of them: warned about
// at their line and ignored (pbrt-v4 reports unused parameters alike), so a scene renders
// with any integrator. A key that no integrator knows stays an error (reject_unused).
void ignore_foreign(const ParamSet& params, const IntegratorInfo& info, RenderSettings& r) {
    const std::string running = std::string(" by type=\"") + info.name + "\"";
    auto ignored = [&](const char* key, uint32_t cap, const std::string& what) {
        params.warn(key, what + " applies to " + integrators_with(cap) + "; ignored" + running);
    };
    if (r.adaptive.enabled && !info.has(kCapCamera)) {
        ignored("adaptive", kCapCamera, "adaptive sampling");
        r.adaptive.enabled = false;
    }
    if (r.indirect == IndirectMode::IrradianceCache && !info.has(kCapIrradianceCache)) {
        ignored("indirect", kCapIrradianceCache, "indirect=\"irradiance_cache\"");
        r.indirect = IndirectMode::FinalGather;
    }
    if (r.cache.secondary == CacheSecondary::Photon && !info.has(kCapPhotonMap)) {
        ignored("cache_secondary", kCapPhotonMap, "cache_secondary=\"photon\"");
        r.cache.secondary = CacheSecondary::Auto;
    }
    // Light paths start by power; bidirectional MIS needs a light's choice independent of
    // the point it lights, so bdpt, bpm and vcm keep power selection for their s = 1 too.
    if (r.regularize && !info.has(kCapRegularize)) {
        ignored("regularize", kCapRegularize, "regularize");
        r.regularize = false;
    }
    if (r.light_selection != LightSelection::Power && !info.has(kCapLightSelection)) {
        ignored("light_selection", kCapLightSelection, "light_selection");
        r.light_selection = LightSelection::Power;
    }
    // Keys that only another integrator's own parse reads (ao_samples for ao).
    for (const IntegratorInfo& other : integrators()) {
        if (&other == &info || !other.parse) continue;
        ParamSet probe = params;
        RenderSettings scratch = r;
        const std::vector<std::string> before = probe.read_keys();
        try {
            other.parse(probe, scratch);
        } catch (const InputError&) {
            // Its values are its own business; only which keys it reads matters here.
        }
        std::vector<std::string> theirs;
        for (const std::string& k : probe.read_keys())
            if (std::find(before.begin(), before.end(), k) == before.end()) theirs.push_back(k);
        params.warn_unused(
            theirs, std::string("belongs to type=\"") + other.name + "\"; ignored" + running);
    }
}

}  // namespace

RenderSettings render_settings(const ParamSet& params) {
    const std::string type = params.text("type", "raytracer");
    const IntegratorInfo* info = find_integrator(type);
    if (!info)
        params.fail("type", "unknown renderer type '" + type + "' (" + integrator_list() + ")");
    // An alias becomes the name.
    const IntegratorTraits traits{info->name, info->caps, integrators_with};
    RenderSettings r = parse_render_settings(params, traits);
    if (info->parse) info->parse(params, r);
    ignore_foreign(params, *info, r);
    if (const std::optional<SettingsProblem> p = capability_problem(*info, r))
        params.fail(p->key, p->message);
    params.reject_unused();
    r.warnings = params.warnings();
    return r;
}

}  // namespace foton
