#pragma once
// Metropolis light transport in primary sample space (`type="mlt"`; Kelemen et al. 2002, the
// photon-mapping thesis' survey of 4.1.6): a baseline for researchers beside the unbiased
// Monte Carlo integrators. A sample is a vector of uniform numbers, and Markov chains move
// through that space towards the samples that carry light. What a vector means is
// `mlt_paths` (mlt_paths.h): "path", the path tracer's path (film position, lens, then
// kPathDimsPerBounce per bounce: path_sampler.h's `primary` kind; NEE + MIS, `max_depth`,
// `rr_depth`), or "bdpt", a camera and a light subpath with all of bdpt's MIS-weighted
// strategies between them (Kelemen et al.'s original MLT over bidirectional paths; pbrt-v4's
// mlt mutates bidirectional paths too, one strategy at a time). A sample deposits
// contributions on one or more pixels; the target f is the sum of their luminances:
//   - a bootstrap of `mlt_bootstrap` independent vectors seeds the chains, drawn from it in
//     proportion to f (no start-up bias); with every large step's f it estimates b = E[f],
//     the image's scale;
//   - each step proposes a fresh vector with probability `large_step` (0.3) or moves every
//     number by a Gaussian of width `mlt_sigma` (0.01), wrapped into [0, 1);
//   - the proposal is accepted with a = min(1, f(y) / f(x)); both states splat their
//     contributions with the expected-value weights a / f(y) and (1 - a) / f(x) (Veach's, as
//     pbrt's MLT);
//   - pixel = b * pixels / mutations * (its splats); mutations = --spp per pixel.
// The proposals of all chains are traced as one wavefront batch per step, in groups of 256
// chains over the threads; the splats are added in chain order, so the image depends on the
// seed only, not on the threads. One process only (under mpirun it says so).
#include <cstdint>

#include "engine/accel/intersector.h"
#include "engine/core/params.h"
#include "engine/transport/run/render_options.h"
#include "engine/transport/run/render_settings.h"

namespace foton {

// Which paths the chains mutate (mlt_paths.h).
enum class MltPathKind : uint8_t { Path, Bidirectional };

struct MltSettings {
    uint32_t chains = 1024;       // Markov chains (a fixed count: the image ignores threads)
    uint64_t bootstrap = 100000;  // vectors that estimate b and seed the chains
    float large_step = 0.3f;      // probability of a fresh vector
    float sigma = 0.01f;          // the small step's width in primary sample space
    MltPathKind paths = MltPathKind::Path;  // mlt_paths: path or bdpt
};

// The row's parse: mlt_chains, mlt_bootstrap, large_step, mlt_sigma, mlt_paths into
// RenderSettings::own.
void parse_mlt(const ParamSet& params, RenderSettings& settings);
RenderResult render_mlt(const Scene& scene, const RenderSettings& settings,
                        const Intersector& accel, const RenderOptions& options);

}  // namespace foton
