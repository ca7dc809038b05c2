#include "render_settings.h"

namespace foton {

namespace {

constexpr uint64_t kMaxCount = kMaxSamplesPerPass;
const EnumTable<Lighting> kLighting{
    {{"all", Lighting::All}, {"direct", Lighting::Direct}, {"indirect", Lighting::Indirect}}};

void parse_sampling(const ParamSet& p, RenderSettings& r) {
    // aa_samples is the first thesis' name; spp (and --spp, which sets it) wins over it.
    r.run.spp = uint32_t(p.integer("aa_samples", r.run.spp, 1, kMaxCount));
    r.run.spp = uint32_t(p.integer("spp", r.run.spp, 1, kMaxCount));
    r.run.threads = int(p.integer("num_threads", 0, 0, kMaxThreads));
    r.sampler = p.choice("sampler", sampler_names(), r.sampler);
    r.max_depth = uint32_t(p.integer("max_depth", r.max_depth, 0, 1000));
    r.min_contribution = p.real("min_contribution", r.min_contribution, 0.f);
    r.run.seed = p.integer("seed", r.run.seed);
    r.run.time_limit = p.real("time", 0.f, 0.f);
    AdaptiveSettings& ad = r.adaptive;
    ad.enabled = p.boolean("adaptive", ad.enabled);
    ad.pilot = uint32_t(p.integer("adaptive_pilot", ad.pilot, 1, kMaxCount));
    ad.max_spp = uint32_t(p.integer("adaptive_max_spp", ad.max_spp, 1, kMaxCount));
    ad.threshold = p.positive("adaptive_threshold", ad.threshold);
    ad.unbiased = p.boolean("adaptive_unbiased", ad.unbiased);
    if (ad.max_spp < ad.pilot) p.fail("adaptive_max_spp", "max_spp must be at least pilot");
}

void parse_path(const ParamSet& p, RenderSettings& r) {
    r.mis = p.choice("mis", mis_names(), r.mis, "mis heuristic");
    r.mis_beta = p.real("mis_beta", r.mis_beta, 1.f, 16.f);
    if (p.has("mis_beta") && r.mis != MisHeuristic::Power)
        p.fail("mis_beta", "mis_beta is the power heuristic's exponent: it needs mis=power");
    r.nee = p.boolean("nee", r.nee);
    static const EnumTable<bool> kShading{{{"simd", true}, {"scalar", false}}};
    r.simd_shading = p.choice("shading", kShading, r.simd_shading);
    r.regularize = p.boolean("regularize", r.regularize);
    static const EnumTable<LightSelection> kSelection{{{"power", LightSelection::Power},
                                                       {"uniform", LightSelection::Uniform},
                                                       {"bvh", LightSelection::Bvh}}};
    r.light_selection = p.choice("light_selection", kSelection, r.light_selection);
    r.projection_maps = p.boolean("projection_maps", r.projection_maps);
    r.rr_depth = uint32_t(p.integer("rr_depth", r.rr_depth, 0, kNoRoulette));
    r.light_samples = uint32_t(p.integer("light_samples", r.light_samples, 1, kMaxCount));
}

// aov="albedo,normal,...": `all` is every AOV the integrator makes (variance needs pixel
// samples, which only camera integrators have; asked for by name elsewhere, it is an error).
void parse_aovs(const ParamSet& p, const IntegratorTraits& it, RenderSettings& r) {
    if (!p.has("aov")) return;
    const std::string text = p.text("aov", "");
    std::string bad;
    uint32_t named = 0;
    if (!parse_aov_list(text, r.aovs, bad, &named))
        p.fail("aov", "unknown AOV '" + bad + "' (" + aov_names().list() + ")");
    for (const AovRequirement& q : kAovRequirements) {
        if (it.has(q.cap) || !(r.aovs & q.aov)) continue;
        if (named & q.aov)
            p.fail("aov", std::string(q.needs) + " " + it.names_with(q.cap) + ", not type=\"" +
                              it.name + "\"");
        r.aovs &= ~q.aov;  // from `all`
    }
}

}  // namespace

RenderSettings parse_render_settings(const ParamSet& params, const IntegratorTraits& it) {
    RenderSettings r;
    r.integrator = it.name;
    parse_sampling(params, r);
    parse_path(params, r);
    parse_aovs(params, it, r);
    parse_photon_settings(params, r.photon);
    if (r.photon.direct_control_variate && r.integrator != "photon") {
        params.warn("direct_estimator",
                    "direct_estimator applies to type=\"photon\"; ignored by "
                    "type=\"" +
                        it.name + "\"");
        r.photon.direct_control_variate = false;
    }
    if (r.photon.importons > 0 && r.integrator != "photon") {
        params.warn("importons",
                    "importons apply to type=\"photon\"; ignored by type=\"" + it.name + "\"");
        r.photon.importons = 0;
    }
    if (r.photon.reverse_lookup &&
        (r.integrator != "photon" || r.photon.mode != PhotonMode::FinalGather)) {
        params.warn("photon_lookup",
                    "photon_lookup=reverse applies to type=\"photon\" with "
                    "mode=\"final_gather\"; ignored");
        r.photon.reverse_lookup = false;
    }
    if (r.photon.stop_error > 0.f && r.integrator != "ppm" && r.integrator != "sppm") {
        params.warn("stop_error",
                    "stop_error applies to type=\"ppm\" and type=\"sppm\"; ignored by type=\"" +
                        it.name + "\"");
        r.photon.stop_error = 0.f;
    }
    if (r.photon.adaptive_photons && r.integrator != "ppm" && r.integrator != "sppm") {
        params.warn("adaptive_photons",
                    "adaptive_photons applies to type=\"ppm\" and type=\"sppm\"; ignored by "
                    "type=\"" +
                        it.name + "\"");
        r.photon.adaptive_photons = false;
    }
    parse_cache_settings(params, r.indirect, r.cache);
    parse_path_guide_settings(params, it, r.guide, r.rr_depth);
    parse_bidir_settings(params, it, r.mis, r.bidir);
    r.lighting = params.choice("lighting", kLighting, r.lighting);
    if (r.lighting != Lighting::All && !it.has(kCapLightingSplit)) {
        params.warn("lighting", "lighting=direct|indirect applies to " +
                                    it.names_with(kCapLightingSplit) + "; ignored by type=\"" +
                                    it.name + "\"");
        r.lighting = Lighting::All;
    }
    if (r.lighting != Lighting::All) {
        if (r.indirect == IndirectMode::IrradianceCache)
            params.fail("lighting",
                        "lighting=direct|indirect and indirect=\"irradiance_cache\" "
                        "do not combine");
    }
    if (r.guide.enabled && r.indirect == IndirectMode::IrradianceCache)
        params.fail("guided", "guided paths and indirect=\"irradiance_cache\" do not combine");
    return r;
}

}  // namespace foton
