#pragma once
// Progressive photon mapping (Hachisuka et al. 2008) and its stochastic form (Hachisuka &
// Jensen 2009): the photon-mapping thesis' future work. Every pixel keeps a visible point
// with a radius R, a photon count N and an accumulated flux tau. A pass traces photons,
// balances them into the kd-tree kernel, and lets every visible point gather the photons
// within its own radius (gathering per point keeps the pass lock-free and deterministic);
// then N' = N + alpha M, R' = R sqrt(N' / (N + M)), tau' = (tau + Phi) R'^2 / R^2. Direct
// light is estimated by next event estimation at the visible point, so first-hit photons are
// not counted. The pixel is L = (sum of direct) / passes + tau / (photons emitted pi R^2).
//   sppm: new visible points every pass (a new camera sample per pixel): consistent, and
//         anti-aliased and glossy-correct in the limit;
//   ppm:  the visible points of the first pass are kept.
#include "engine/accel/intersector.h"
#include "engine/transport/run/render_options.h"
#include "engine/transport/run/render_settings.h"

namespace foton {

RenderResult render_progressive_photons(const Scene& scene, const RenderSettings& settings,
                                        const Intersector& accel, const RenderOptions& options,
                                        bool stochastic);
// The two entries of the integrator table.
inline RenderResult render_sppm(const Scene& scene, const RenderSettings& settings,
                                const Intersector& accel, const RenderOptions& options) {
    return render_progressive_photons(scene, settings, accel, options, true);
}
inline RenderResult render_ppm(const Scene& scene, const RenderSettings& settings,
                               const Intersector& accel, const RenderOptions& options) {
    return render_progressive_photons(scene, settings, accel, options, false);
}

}  // namespace foton
