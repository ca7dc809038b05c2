#pragma once
// The renderer's settings (<renderer> in the XML format, --set on the command line), typed
// and checked: parse_render_settings reads them from a ParamSet, reporting every bad value
// at its file and line and rejecting keys it does not know.
#include <cstdint>
#include <string>

#include "engine/core/params.h"
#include "engine/core/sampler.h"

namespace foton {

// raytracer: the first thesis' Whitted model; path, light, distributed: the Monte Carlo
// estimators of the photon-mapping thesis.
enum class IntegratorType { Whitted, Path, Light, Distributed, Photon, Sppm, Ppm };
const EnumTable<IntegratorType>& integrator_names();
const char* integrator_name(IntegratorType t);
bool parse_integrator(const std::string& s, IntegratorType& out);

// How next event estimation and BSDF sampling are combined in `path`.
enum class MisHeuristic { Balance, Power, Maximum, None };
const EnumTable<MisHeuristic>& mis_names();
const char* mis_name(MisHeuristic h);
bool parse_mis(const std::string& s, MisHeuristic& out);

struct AdaptiveSettings {
    bool enabled = false;
    uint32_t pilot = 8;       // samples every pixel gets first
    uint32_t max_spp = 256;   // never more than this per pixel
    float threshold = 0.02f;  // target relative standard error of a pixel's mean luminance
    // Kirk & Arvo: the pilot samples only decide the count and are not averaged in, which
    // keeps the estimate unbiased (the default, iterative rule stops on the very samples it
    // averages, a small bias).
    bool unbiased = false;
};

// The photon estimate's envelope (the thesis' sphere, or its flattened ellipsoid: a disc) and
// its filters (none, cone, Gauss, Simpson), used by photon_map.h.
enum class PhotonEnvelope : uint8_t { Sphere, Disc };
enum class PhotonFilter : uint8_t { None, Cone, Gauss, Simpson };
const EnumTable<PhotonEnvelope>& envelope_names();
const EnumTable<PhotonFilter>& filter_names();
const char* filter_name(PhotonFilter f);

// Two-pass photon mapping (the photon-mapping thesis, chapters 5-6).
enum class PhotonMode { FinalGather, DirectVisualisation };
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
struct PhotonSettings {
    uint64_t global_photons = 200000;   // emitted for the global map
    uint64_t caustic_photons = 200000;  // emitted for the caustic map (0: none)
    uint32_t k = 100, caustic_k = 50;   // photons per estimate
    float max_radius = 0.f;             // 0: 5 % of the scene's bounding radius
    float caustic_radius = 0.f;         // 0: 2 % of it
    PhotonEnvelope envelope = PhotonEnvelope::Disc;
    PhotonFilter filter = PhotonFilter::None;  // of the global map
    PhotonFilter caustic_filter = PhotonFilter::None;
    float cone_k = 1.1f;
    PhotonMode mode = PhotonMode::FinalGather;
    uint32_t gather_rays = 64;       // final-gather rays per visible point and pixel sample
    uint32_t irradiance_stride = 4;  // precomputed irradiance at every n-th photon (0: off)
    bool unscaled_roulette = false;
    // Shadow photons (Jensen 1995): a shadow map decides next event estimation's visibility
    // where the nearest photons agree (only direct ones: lit; only shadow ones: dark).
    bool shadow_photons = false;
    // Split the global map into a direct map (first-hit photons) and an indirect map: direct
    // visualisation then takes direct light from next event estimation (ray traced) and only
    // the indirect light from the photons.
    bool split_direct = false;
    // Photon-guided final gathering (Jensen 1995): gather directions at diffuse visible points
    // drawn from a histogram of the nearby indirect photons' incident power.
    bool guided_gather = false;
    uint32_t guide_photons = 400;  // nearest photons in the guide's histogram
    // Progressive photon mapping (ppm, sppm).
    float initial_radius = 0.f;     // 0: 1 % of the scene's bounding radius
    float alpha = 2.f / 3.f;        // fraction of new photons kept per pass
    uint64_t photons_per_pass = 0;  // 0: one per pixel
};

struct RenderSettings {
    IntegratorType integrator = IntegratorType::Whitted;
    uint32_t spp = 1;  // aa_samples
    int threads = 0;   // 0 = all hardware threads
    SamplerKind sampler = SamplerKind::Jittered;
    // raytracer: specular bounces after the camera ray; path/light: scattering vertices.
    uint32_t max_depth = 8;
    float min_contribution = 1e-3f;  // raytracer: cut-off on a path's weight
    uint64_t seed = 0;
    MisHeuristic mis = MisHeuristic::Power;
    bool nee = true;             // path: next event estimation (false = BSDF sampling only)
    uint32_t rr_depth = 3;       // Russian roulette from this many scattering vertices on
    float time_limit = 0.f;      // seconds; > 0 renders passes until the time is up
    uint32_t light_samples = 1;  // distributed: shadow rays per light at each hit
    AdaptiveSettings adaptive;
    PhotonSettings photon;
    // photon (final-gather mode): at every diffuse visible point; path: at the first diffuse
    // vertex of each camera path (after specular ones only).
    IndirectMode indirect = IndirectMode::FinalGather;
    CacheSettings cache;
};

// Reads every renderer setting from `params` (its keys: see scenes/README.md), then rejects
// any key it did not read.
RenderSettings parse_render_settings(const ParamSet& params);

}  // namespace foton
