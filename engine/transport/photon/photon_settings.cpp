#include "photon_settings.h"

namespace foton {

const EnumTable<PhotonEnvelope>& envelope_names() {
    static const EnumTable<PhotonEnvelope> t{
        {{"sphere", PhotonEnvelope::Sphere}, {"disc", PhotonEnvelope::Disc}}};
    return t;
}
const EnumTable<PhotonFilter>& filter_names() {
    static const EnumTable<PhotonFilter> t{{{"none", PhotonFilter::None},
                                            {"cone", PhotonFilter::Cone},
                                            {"gauss", PhotonFilter::Gauss},
                                            {"simpson", PhotonFilter::Simpson},
                                            {"gauss_thesis", PhotonFilter::GaussThesis}}};
    return t;
}
const char* filter_name(PhotonFilter f) {
    return filter_names().name(f);
}

namespace {
const EnumTable<PhotonMode> kPhotonModes{
    {{"final_gather", PhotonMode::FinalGather},
     {"direct_visualisation", PhotonMode::DirectVisualisation},
     {"direct_visualization", PhotonMode::DirectVisualisation}}};
const EnumTable<bool> kPhotonRoulette{{{"unbiased", false}, {"unscaled", true}}};
const EnumTable<bool> kPhotonLookups{{{"forward", false}, {"reverse", true}}};
const EnumTable<bool> kDirectEstimators{{{"sample", false}, {"control_variate", true}}};
}  // namespace

void parse_photon_settings(const ParamSet& p, PhotonSettings& s) {
    s.global_photons = p.integer("global_photons", s.global_photons, 0, 4000000000ull);
    s.caustic_photons = p.integer("caustic_photons", s.caustic_photons, 0, 4000000000ull);
    s.k = uint32_t(p.integer("k", s.k, 1, 4096));
    s.caustic_k = uint32_t(p.integer("caustic_k", s.caustic_k, 1, 4096));
    s.max_radius = p.real("max_radius", s.max_radius, 0.f);
    s.caustic_radius = p.real("caustic_radius", s.caustic_radius, 0.f);
    s.cone_k = p.real("cone_k", s.cone_k, 1.f);
    s.gather_rays = uint32_t(p.integer("gather_rays", s.gather_rays, 0, 1000000));
    s.shadow_photons = p.boolean("shadow_photons", s.shadow_photons);
    if (p.has("shadow_visibility")) {
        const std::string v = p.text("shadow_visibility");
        if (v != "rays" && v != "estimate")
            p.fail("shadow_visibility", "shadow_visibility is rays or estimate, not '" + v + "'");
        s.shadow_estimate = v == "estimate";
        if (s.shadow_estimate && !s.shadow_photons)
            p.fail("shadow_visibility", "shadow_visibility=estimate needs shadow_photons=true");
    }
    s.split_direct = p.boolean("split_direct", s.split_direct);
    s.importons = p.integer("importons", s.importons, 0, 1000000000ull);
    s.reverse_lookup = p.choice("photon_lookup", kPhotonLookups, s.reverse_lookup, "photon lookup");
    s.direct_control_variate = p.choice("direct_estimator", kDirectEstimators,
                                        s.direct_control_variate, "direct estimator");
    s.guided_gather = p.boolean("guided_gather", s.guided_gather);
    s.compact_power = p.boolean("compact_power", s.compact_power);
    s.guide_photons = uint32_t(p.integer("guide_photons", s.guide_photons, 1, 4096));
    s.initial_radius = p.real("initial_radius", s.initial_radius, 0.f);
    s.alpha = p.real("alpha", s.alpha);
    if (!(s.alpha > 0.f && s.alpha <= 1.f)) p.fail("alpha", "alpha must be in (0, 1]");
    s.photons_per_pass = p.integer("photons_per_pass", s.photons_per_pass, 0, 4000000000ull);
    s.adaptive_photons = p.boolean("adaptive_photons", s.adaptive_photons);
    s.stop_error = p.real("stop_error", s.stop_error, 0.f);
    s.stop_confidence = p.real("stop_confidence", s.stop_confidence);
    if (!(s.stop_confidence > 0.f && s.stop_confidence < 1.f))
        p.fail("stop_confidence", "stop_confidence must be in (0, 1)");
    s.irradiance_stride = uint32_t(p.integer("irradiance_stride", s.irradiance_stride, 0, 1000000));
    s.envelope = p.choice("envelope", envelope_names(), s.envelope);
    s.filter = p.choice("filter", filter_names(), s.filter);
    s.caustic_filter = p.choice("caustic_filter", filter_names(), s.caustic_filter, "filter");
    s.mode = p.choice("mode", kPhotonModes, s.mode, "photon mode");
    s.unscaled_roulette = p.choice("photon_rr", kPhotonRoulette, s.unscaled_roulette);
}

}  // namespace foton
