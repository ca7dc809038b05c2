#pragma once
// Bidirectional path tracing (`bdpt`), bidirectional photon mapping (`bpm`) and vertex
// connection and merging (`vcm`) on one core (Georgiev et al. 2012): an iteration traces one
// light subpath per pixel and stores its vertices, then one camera subpath per pixel that
// connects to its own light path (bdpt, vcm) and merges with the vertices of all of them
// within a radius that shrinks from iteration to iteration as in progressive photon mapping
// (bpm, vcm). The iteration is a graph of stages: light paths -> light vertices (and their
// merge grid) -> camera paths, and the light paths' camera splats. A pass is `spp` iterations.
#include "engine/accel/intersector.h"
#include "engine/scene/scene.h"
#include "engine/transport/run/render_options.h"
#include "engine/transport/run/render_settings.h"

namespace foton {

RenderResult render_bdpt(const Scene& scene, const RenderSettings& settings,
                         const Intersector& accel, const RenderOptions& options);
RenderResult render_bpm(const Scene& scene, const RenderSettings& settings,
                        const Intersector& accel, const RenderOptions& options);
RenderResult render_vcm(const Scene& scene, const RenderSettings& settings,
                        const Intersector& accel, const RenderOptions& options);

}  // namespace foton
