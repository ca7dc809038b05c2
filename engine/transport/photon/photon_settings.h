#pragma once
// Photon mapping's settings (photon, sppm, ppm), read from the renderer's ParamSet.
#include <cstdint>

#include "engine/core/params.h"

namespace foton {

// The photon estimate's envelope (the thesis' sphere, or its flattened ellipsoid: a disc) and
// its filters (none, cone, Gauss, Simpson), used by photon_map.h.
enum class PhotonEnvelope : uint8_t { Sphere, Disc };
// GaussThesis: the photon-mapping thesis' Gauss filter as printed (6.1.2), its weights used
// with 1 / (pi r^2) and not normalised: it integrates to 0.531 over the disc, the darkening
// chapter 7 reports. Gauss is the same shape normalised to one.
enum class PhotonFilter : uint8_t { None, Cone, Gauss, Simpson, GaussThesis };
const EnumTable<PhotonEnvelope>& envelope_names();
const EnumTable<PhotonFilter>& filter_names();
const char* filter_name(PhotonFilter f);

// Two-pass photon mapping (the photon-mapping thesis, chapters 5-6).
enum class PhotonMode { FinalGather, DirectVisualisation };
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
    // In a penumbra (both kinds near), shadow_visibility="estimate" takes the visibility from
    // the photons instead of the ray (the thesis' 6.6): the lit fraction n_n / (n_n + n_s)
    // of the nearest direct (n_n) and shadow (n_s) photons. Biased; saves every ray.
    bool shadow_estimate = false;
    // direct_estimator="control_variate" (photon): next event estimation at visible points with the
    // unshadowed light as a control variate (the thesis' 3.2.4;
    // transport/common/direct_control_variate.h): exact in fully lit regions of Lambertian surfaces
    // under polygonal lights.
    bool direct_control_variate = false;
    // importons=N (photon): N importons from the camera decide where photons are stored
    // (importon_map.h, the thesis' 6.7); 0: every photon is stored.
    uint64_t importons = 0;
    // photon_lookup="reverse" (photon, final gathering): the gather hits' full estimates by
    // reverse photon mapping (Havran et al. 2005; reverse_photons.h) instead of kNN searches.
    bool reverse_lookup = false;
    // Split the global map into a direct map (first-hit photons) and an indirect map: direct
    // visualisation then takes direct light from next event estimation (ray traced) and only
    // the indirect light from the photons.
    bool split_direct = false;
    // Photon-guided final gathering (Jensen 1995): gather directions at diffuse visible points
    // drawn from a histogram of the nearby indirect photons' incident power.
    bool guided_gather = false;
    // Ward's RGBE for the photons' power and the precomputed irradiance (4 bytes, not 12;
    // the thesis' 6.5): photon, sppm, ppm and the path guide's maps.
    bool compact_power = false;
    uint32_t guide_photons = 400;  // nearest photons in the guide's histogram
    // Progressive photon mapping (ppm, sppm).
    float initial_radius = 0.f;     // 0: 1 % of the scene's bounding radius
    float alpha = 2.f / 3.f;        // fraction of new photons kept per pass
    uint64_t photons_per_pass = 0;  // 0: one per pixel
    // Adaptive photon tracing (adaptive_photons.h; Hachisuka and Jensen 2011): photon paths
    // from Markov chains over the paths the pass's visible points see.
    bool adaptive_photons = false;
    // The stopping rule (ppm_error_bound.h; the thesis' 8.1.1): stop once the mean per-pixel
    // error bound at `stop_confidence` is at most `stop_error` times the image's mean
    // luminance; 0: off (the passes are --spp or --time's).
    float stop_error = 0.f;
    float stop_confidence = 0.95f;
};

// Reads the photon keys (global_photons, k, filter, mode, alpha, ...) into `s`.
void parse_photon_settings(const ParamSet& params, PhotonSettings& s);

}  // namespace foton
