#pragma once
// Volumetric photon mapping (`type="vpm"`; Jensen & Christensen 1998, the photon-mapping
// thesis' future work), made progressive and consistent by shrinking radii (Knaus & Zwicker
// 2011's probabilistic PPM, in 3D for the volume as Jarosz et al. 2011 do).
//
// A pass traces photons through the media (volume_photons.h) into a surface and a volume map,
// then one camera path per pixel: through specular surfaces and interfaces, its flights
// sampled as volpath's; where it first scatters in a medium it takes the volume radiance
// estimate, sum p(wo, wi_p) power_p / (4/3 pi r_v^3) over the volume photons within r_v, and
// where it first meets a non-delta surface the surface estimate, sum f(wo, wi_p) power_p /
// (pi r_s^2) (its delta lobes are followed on besides). Direct light there comes from one
// light sample (next event estimation with the media's transmittance, as Jensen computes it
// by ray tracing), the photons giving only what arrived after a bounce or a scattering
// (`direct="photons"`: all of it from photons). Emitters seen directly or through specular
// chains add their radiance. The image is the mean of the passes' estimates; after
// pass i the radii shrink as r_s^2 *= (i + alpha) / (i + 1) and r_v^3 *= (i + alpha) / (i + 1),
// so bias and variance both vanish (alpha = the photon settings' `alpha`).
//
// Settings: photons_per_pass (default one per pixel), initial_radius (surfaces; default 1 %
// of the scene's bounding radius), volume_radius (default 5 %), estimator (point or beam: the
// beam radiance estimate of Jarosz et al. 2008, whose disc radius shrinks as a surface's
// does), alpha (2/3), max_depth
// (bounces of photons and of camera paths through specular surfaces). Emitting media send no
// photons: such a scene is refused (volpath renders it).
#include "engine/accel/intersector.h"
#include "engine/core/params.h"
#include "engine/transport/run/render_options.h"
#include "engine/transport/run/render_settings.h"

namespace foton {

struct VpmSettings {
    float volume_radius = 0.f;  // 0: 5 % of the scene's bounding radius
    // direct="photons": the photons estimate the direct light too (pure density estimation);
    // by default one light sample at the path's last vertex does (through the media it
    // crosses), and photons straight from a light are left out of the estimates.
    bool direct_photons = false;
    // estimator="beam": the volume photons reach a camera ray as discs, every photon within
    // r_v of the whole segment counting at once (the beam radiance estimate, beam_estimate.h);
    // the default "point" estimate gathers a ball at one point a flight samples.
    bool beam = false;
};

void parse_vpm(const ParamSet& params, RenderSettings& settings);
RenderResult render_vpm(const Scene& scene, const RenderSettings& settings,
                        const Intersector& accel, const RenderOptions& options);

}  // namespace foton
