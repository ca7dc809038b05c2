#include "render_settings.h"

namespace foton {

const EnumTable<IntegratorType>& integrator_names() {
    static const EnumTable<IntegratorType> t{{{"raytracer", IntegratorType::Whitted},
                                              {"whitted", IntegratorType::Whitted},
                                              {"path", IntegratorType::Path},
                                              {"light", IntegratorType::Light},
                                              {"distributed", IntegratorType::Distributed},
                                              {"photon", IntegratorType::Photon},
                                              {"sppm", IntegratorType::Sppm},
                                              {"ppm", IntegratorType::Ppm}}};
    return t;
}
const char* integrator_name(IntegratorType t) {
    return integrator_names().name(t);
}
bool parse_integrator(const std::string& s, IntegratorType& out) {
    return integrator_names().parse(s, out);
}

const EnumTable<MisHeuristic>& mis_names() {
    static const EnumTable<MisHeuristic> t{{{"balance", MisHeuristic::Balance},
                                            {"power", MisHeuristic::Power},
                                            {"max", MisHeuristic::Maximum},
                                            {"maximum", MisHeuristic::Maximum},
                                            {"none", MisHeuristic::None}}};
    return t;
}
const char* mis_name(MisHeuristic h) {
    return mis_names().name(h);
}
bool parse_mis(const std::string& s, MisHeuristic& out) {
    return mis_names().parse(s, out);
}

const EnumTable<PhotonEnvelope>& envelope_names() {
    static const EnumTable<PhotonEnvelope> t{
        {{"sphere", PhotonEnvelope::Sphere}, {"disc", PhotonEnvelope::Disc}}};
    return t;
}
const EnumTable<PhotonFilter>& filter_names() {
    static const EnumTable<PhotonFilter> t{{{"none", PhotonFilter::None},
                                            {"cone", PhotonFilter::Cone},
                                            {"gauss", PhotonFilter::Gauss},
                                            {"simpson", PhotonFilter::Simpson}}};
    return t;
}
const char* filter_name(PhotonFilter f) {
    return filter_names().name(f);
}

namespace {

const EnumTable<SamplerKind> kSamplers{{{"regular", SamplerKind::Regular},
                                        {"random", SamplerKind::Random},
                                        {"jittered", SamplerKind::Jittered},
                                        {"hammersley", SamplerKind::Hammersley}}};
const EnumTable<PhotonMode> kPhotonModes{
    {{"final_gather", PhotonMode::FinalGather},
     {"direct_visualisation", PhotonMode::DirectVisualisation},
     {"direct_visualization", PhotonMode::DirectVisualisation}}};
const EnumTable<bool> kPhotonRoulette{{{"unbiased", false}, {"unscaled", true}}};
const EnumTable<IndirectMode> kIndirect{{{"final_gather", IndirectMode::FinalGather},
                                         {"irradiance_cache", IndirectMode::IrradianceCache}}};
const EnumTable<bool> kCacheWeight{{{"notes", false}, {"ward", true}}};
const EnumTable<bool> kCacheRadius{{{"harmonic", false}, {"minimum", true}}};
const EnumTable<CacheSecondary> kCacheSecondary{{{"photon", CacheSecondary::Photon},
                                                 {"direct", CacheSecondary::Direct},
                                                 {"path", CacheSecondary::Path},
                                                 {"cache", CacheSecondary::Cache},
                                                 {"occlusion", CacheSecondary::Occlusion}}};

constexpr uint64_t kMaxCount = 100000000;

void parse_sampling(const ParamSet& p, RenderSettings& r) {
    r.integrator = p.choice("type", integrator_names(), r.integrator, "renderer type");
    r.spp = uint32_t(p.integer("spp", r.spp, 1, kMaxCount));
    r.spp = uint32_t(p.integer("aa_samples", r.spp, 1, kMaxCount));  // the first thesis' name
    r.threads = int(p.integer("num_threads", 0, 0, 65536));
    r.sampler = p.choice("sampler", kSamplers, r.sampler);
    r.max_depth = uint32_t(p.integer("max_depth", r.max_depth, 0, 1000));
    r.min_contribution = p.real("min_contribution", r.min_contribution, 0.f);
    r.seed = p.integer("seed", r.seed);
    r.time_limit = p.real("time", 0.f, 0.f);
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
    r.nee = p.boolean("nee", r.nee);
    r.rr_depth = uint32_t(p.integer("rr_depth", r.rr_depth, 0, 1000000));
    r.light_samples = uint32_t(p.integer("light_samples", r.light_samples, 1, kMaxCount));
}

void parse_photon(const ParamSet& p, PhotonSettings& s) {
    s.global_photons = p.integer("global_photons", s.global_photons, 0, 4000000000ull);
    s.caustic_photons = p.integer("caustic_photons", s.caustic_photons, 0, 4000000000ull);
    s.k = uint32_t(p.integer("k", s.k, 1, 4096));
    s.caustic_k = uint32_t(p.integer("caustic_k", s.caustic_k, 1, 4096));
    s.max_radius = p.real("max_radius", s.max_radius, 0.f);
    s.caustic_radius = p.real("caustic_radius", s.caustic_radius, 0.f);
    s.cone_k = p.real("cone_k", s.cone_k, 1.f);
    s.gather_rays = uint32_t(p.integer("gather_rays", s.gather_rays, 0, 1000000));
    s.shadow_photons = p.boolean("shadow_photons", s.shadow_photons);
    s.split_direct = p.boolean("split_direct", s.split_direct);
    s.guided_gather = p.boolean("guided_gather", s.guided_gather);
    s.guide_photons = uint32_t(p.integer("guide_photons", s.guide_photons, 1, 4096));
    s.initial_radius = p.real("initial_radius", s.initial_radius, 0.f);
    s.alpha = p.real("alpha", s.alpha);
    if (!(s.alpha > 0.f && s.alpha <= 1.f)) p.fail("alpha", "alpha must be in (0, 1]");
    s.photons_per_pass = p.integer("photons_per_pass", s.photons_per_pass, 0, 4000000000ull);
    s.irradiance_stride = uint32_t(p.integer("irradiance_stride", s.irradiance_stride, 0, 1000000));
    s.envelope = p.choice("envelope", envelope_names(), s.envelope);
    s.filter = p.choice("filter", filter_names(), s.filter);
    s.caustic_filter = p.choice("caustic_filter", filter_names(), s.caustic_filter, "filter");
    s.mode = p.choice("mode", kPhotonModes, s.mode, "photon mode");
    s.unscaled_roulette = p.choice("photon_rr", kPhotonRoulette, s.unscaled_roulette);
}

void parse_cache(const ParamSet& p, RenderSettings& r) {
    r.indirect = p.choice("indirect", kIndirect, r.indirect);
    CacheSettings& c = r.cache;
    c.samples = uint32_t(p.integer("cache_samples", c.samples, 4, 100000));
    c.ward_weight = p.choice("cache_weight", kCacheWeight, c.ward_weight);
    c.a = p.positive("cache_a", c.a);
    c.kappa = p.positive("cache_kappa", c.kappa);
    c.r_min_pixels = p.positive("cache_r_min", c.r_min_pixels);
    c.r_max_factor = p.real("cache_r_max_factor", c.r_max_factor, 1.f);
    c.minimum_radius = p.choice("cache_radius", kCacheRadius, c.minimum_radius);
    c.gradients = p.boolean("cache_gradients", c.gradients);
    c.visibility = p.boolean("cache_visibility", c.visibility);
    c.secondary = p.choice("cache_secondary", kCacheSecondary, c.secondary);
    c.levels = uint32_t(p.integer("cache_levels", c.levels, 1, 8));
    c.ao_distance = p.real("cache_ao_distance", c.ao_distance, 0.f);
}

}  // namespace

RenderSettings parse_render_settings(const ParamSet& params) {
    RenderSettings r;
    parse_sampling(params, r);
    parse_path(params, r);
    parse_photon(params, r.photon);
    parse_cache(params, r);
    params.reject_unused();
    return r;
}

}  // namespace foton
