#pragma once
// The irradiance cache's settings, read from the renderer's ParamSet.
#include <cstdint>

#include "engine/core/params.h"

namespace foton {

// Indirect diffuse light at the visible points: final-gather rays at every point, or the
// irradiance cache (records computed by the same rays at a few points, interpolated
// elsewhere).
enum class IndirectMode { FinalGather, IrradianceCache };

// What a record's hemisphere rays see at their hits, the lecture notes' four choices: direct
// light only; the global photon map's estimate; path tracing onwards; the cache of the next
// bounce level (one cache per level, the last level's rays seeing direct light only). And
// ambient occlusion: a ray brings the ambient radiance (white without an <ambient> light)
// unless it hits something within cache_ao_distance. Auto: photon under type="photon",
// path under type="path".
enum class CacheSecondary { Auto, Direct, Photon, Path, Cache, Occlusion };

// Ward's irradiance cache (the lecture notes, NPGR010 2011).
struct CacheSettings {
    uint32_t samples = 512;    // hemisphere rays per record, laid out as M x N with N ~ pi M
    bool ward_weight = false;  // Ward's 1 / (d / R + sqrt(1 - n.n_i)) > 1 / a; else the notes'
    float a = 0.3f;            // Ward's accuracy
    float kappa = 2.f;  // the notes' accuracy (1 reaches out to 2 R_i: measured 2.5 % too bright
                        // on the diffuse box, where the features are dark corners)
    float r_min_pixels = 1.5f;    // R_min: this many pixel footprints at the record
    float r_max_factor = 20.f;    // R_max = r_max_factor R_min
    bool minimum_radius = false;  // R_i from the shortest non-grazing ray, not the harmonic mean
    bool gradients = true;
    bool visibility = true;  // shadow ray between p and p_i before a record is used
    CacheSecondary secondary = CacheSecondary::Auto;
    uint32_t levels = 3;      // secondary = cache: cache levels (bounces of indirect light)
    float ao_distance = 0.f;  // secondary = occlusion: 0 = unlimited
};
// Reads `indirect` and the cache_* keys.
void parse_cache_settings(const ParamSet& params, IndirectMode& indirect, CacheSettings& c);

}  // namespace foton
