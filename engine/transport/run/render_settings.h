#pragma once
// The renderer's settings (<renderer> in the XML format, --set and the flags on the command
// line), typed and checked. Each family keeps its own group (photon/photon_settings.h,
// irradiance_cache/cache_settings.h, the MIS heuristic in common/mis.h); render_settings()
// (integrators.h) reads them all from the scene's ParamSet, reporting every bad value at its file
// and line and rejecting keys nobody knows.
#include <any>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "engine/core/params.h"
#include "engine/core/sampler.h"
#include "engine/film/aov.h"
#include "engine/scene/light_selection.h"
#include "engine/transport/bidir/bidir_settings.h"
#include "engine/transport/common/transport_settings.h"
#include "engine/transport/irradiance_cache/cache_settings.h"
#include "engine/transport/path/path_guide_settings.h"
#include "engine/transport/photon/photon_settings.h"
#include "render_options.h"

namespace foton {

// Which light a camera integrator adds up (the photon thesis' chapter 7 renders direct and
// indirect light apart), classified at the first non-specular vertex seen through the camera's
// specular chain: direct light arrives there straight from an emitter (a light sample, or a
// BSDF ray that hits it), indirect light after any bounce, caustics included, as the photon
// maps count it (direct photons are first hits). Emitters seen directly or through mirrors
// count as direct. k is 0 before that vertex, 1 for light straight to it, 2 for the rest.
enum class Lighting : uint8_t { All, Direct, Indirect };
// Whether light reached after k non-specular vertices counts.
inline bool counts(Lighting l, uint32_t k) {
    return l == Lighting::All || (l == Lighting::Direct ? k <= 1 : k >= 2);
}

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

struct RenderSettings {
    std::string integrator = "raytracer";  // a name in integrators()
    // The run's own settings as the file gives them (spp, num_threads, seed, time): the
    // command line starts from these and overrides them with its flags.
    RenderOptions run;
    SamplerKind sampler = SamplerKind::Jittered;
    // raytracer: specular bounces after the camera ray; path/light: scattering vertices.
    uint32_t max_depth = 8;
    float min_contribution = 1e-3f;  // raytracer: cut-off on a path's weight
    MisHeuristic mis = MisHeuristic::Power;
    float mis_beta = 2.f;  // the power heuristic's exponent
    bool nee = true;       // path: next event estimation (false = BSDF sampling only)
    // path: Lambertian vertices through the SIMD shading kernel (false: every vertex one at
    // a time, the kernel's reference)
    bool simd_shading = true;
    // path, volpath: pbrt-v4's `regularize`: after a path's first non-specular vertex its
    // BSDFs are Bsdf::regularized() (biased: less noise from near-specular paths)
    bool regularize = false;
    // path, photon, sppm, ppm: how next event estimation chooses its light
    LightSelection light_selection = LightSelection::Power;
    // Every integrator that emits from the lights: directional lights emit over the geometry
    // only (their projection maps; the photon thesis' 5.3.2), not the whole bounding disc
    bool projection_maps = true;
    uint32_t rr_depth = 3;  // Russian roulette from this many scattering vertices on (guided
                            // paths: kNoRoulette unless given)
    uint32_t light_samples =
        1;  // distributed: shadow rays per light at each hit; raytracer: per environment
    AdaptiveSettings adaptive;
    Lighting lighting = Lighting::All;  // path and photon: all, direct or indirect light only
    PathGuideSettings guide;            // path: photon-guided directions at diffuse vertices
    PhotonSettings photon;
    // photon (final-gather mode): at every diffuse visible point; path: at the first diffuse
    // vertex of each camera path (after specular ones only).
    IndirectMode indirect = IndirectMode::FinalGather;
    CacheSettings cache;
    BidirSettings bidir;
    // The integrator's own settings, read by its row's parse (integrators.h), for keys no other
    // family reads; the integrator any_casts it to its own type.
    std::any own;
    // Extra outputs (film/aov.h's bits): first-hit layers for any integrator, per-pixel variance
    // for camera integrators, the sample counts always.
    uint32_t aovs = 0;
    // "file:line: ..." for each setting that applies to another integrator and was ignored.
    std::vector<std::string> warnings;
};

// Every shared group's keys, checked against what the integrator (`type`, found in the table
// by render_settings() in integrators.h, which is what callers use) supports. Unknown keys are
// rejected there, after the integrator's own parse.
RenderSettings parse_render_settings(const ParamSet& params, const IntegratorTraits& integrator);

}  // namespace foton
