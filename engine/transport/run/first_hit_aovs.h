#pragma once
// The first-hit AOVs of film/aov.h (albedo, normal, depth, position) for any integrator: a
// pass of its own after the render, which traces the camera rays of the render's first pass
// (the same pixel positions, the same sampler; at most kFirstHitSpp per pixel) and records
// what each first hit sees. A pass apart rather than data riding on every integrator's
// camera paths: the light tracer, BDPT and SPPM have no camera ray per pixel sample, and one
// traced ray per sample costs little beside a render.
#include <vector>

#include "engine/accel/intersector.h"
#include "engine/film/aov.h"
#include "engine/scene/scene.h"
#include "render_options.h"
#include "render_settings.h"

namespace foton {

// Samples per pixel of the first-hit pass: the render's spp (its first pass's), at most this.
inline constexpr uint32_t kFirstHitSpp = 64;
// BSDF samples behind each albedo estimate (stratified 4 x 4).
inline constexpr int kAlbedoSamples = 16;

// The layers `settings.aovs` asks for among the first-hit ones, in aov.h's order (none when
// it asks for none). Deterministic: the same for any thread count.
std::vector<AovLayer> render_first_hit_aovs(const Scene& scene, const RenderSettings& settings,
                                            const Intersector& accel, const RenderOptions& opt);

}  // namespace foton
