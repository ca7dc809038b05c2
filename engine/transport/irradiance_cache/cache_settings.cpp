#include "cache_settings.h"

namespace foton {

namespace {
const EnumTable<IndirectMode> kIndirect{{{"final_gather", IndirectMode::FinalGather},
                                         {"irradiance_cache", IndirectMode::IrradianceCache}}};
const EnumTable<bool> kCacheWeight{{{"notes", false}, {"ward", true}}};
const EnumTable<bool> kCacheRadius{{{"harmonic", false}, {"minimum", true}}};
const EnumTable<CacheSecondary> kCacheSecondary{{{"photon", CacheSecondary::Photon},
                                                 {"direct", CacheSecondary::Direct},
                                                 {"path", CacheSecondary::Path},
                                                 {"cache", CacheSecondary::Cache},
                                                 {"occlusion", CacheSecondary::Occlusion}}};

}  // namespace

void parse_cache_settings(const ParamSet& p, IndirectMode& indirect, CacheSettings& c) {
    indirect = p.choice("indirect", kIndirect, indirect);
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

}  // namespace foton
