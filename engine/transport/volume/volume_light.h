#pragma once
// Light tracing through participating media: the light tracer (transport/light/) with medium
// vertices. A light path starts in its light's medium (common/medium_locate.h), samples its
// flights as photons do (common/medium_tracking.h, grid flights batched), scatters in media by
// the Henyey-Greenstein phase function and at surfaces by the BSDF, and passes interfaces.
// Every vertex that can see the eye (the emitting point, each medium vertex, each surface
// vertex with a non-delta BSDF) is joined to the pinhole by a shadow ray through the media on
// the way (common/medium_shadow.h: transmittance, interfaces passed); what arrives is splatted
// onto the pixel it projects to.
//
// Media that emit are refused (light paths start at lights only). Determinism as the light
// tracer's: a path is a pure function of (seed, path), and a chunk's splats keep the order
// of its connections, which depends only on its paths.
#include <cstdint>
#include <vector>

#include "engine/core/ray_batch.h"
#include "engine/core/stats.h"
#include "engine/film/pixel_sums.h"
#include "engine/transport/common/medium_shadow.h"
#include "engine/transport/run/render_context.h"
#include "grid_flights.h"

namespace foton {

struct VolumeLightWorkspace {
    RayBatch rays, next;
    HitBatch hits;
    std::vector<RGB> beta;
    std::vector<int32_t> medium;
    std::vector<uint32_t> bounces, crossings, draws;
    GridFlights flights;  // a round's flights through grid media, as one batch
    std::vector<int32_t> flight_of;
    // The connections to the eye: one slot each, where on the film it lands and what arrived.
    MediumShadowRays shadow;
    std::vector<FilmPoint> shadow_at;
    std::vector<RGB> arrived;
};

class VolumeLightTracer {
  public:
    explicit VolumeLightTracer(const RenderContext& ctx);
    // Traces paths [first, first + count) and appends their splats (LightTracer::trace's).
    void trace(uint64_t first, uint32_t count, VolumeLightWorkspace& ws, std::vector<Splat>& splats,
               RenderStats& stats) const;

  private:
    // A connection from o (in medium `medium`) towards the eye carrying `value` (before the
    // camera's importance), keyed for ratio tracking by the path and its vertex.
    void connect(const Vec3& p, const Vec3& o, int32_t medium, const RGB& value, uint64_t key,
                 VolumeLightWorkspace& ws) const;
    // A surface vertex: the connection to the eye and the BSDF's continuation.
    template <class Uniform>
    void shade_surface(std::size_t r, uint64_t path, VolumeLightWorkspace& ws, Uniform&& u) const;

    const RenderContext ctx_;
    std::vector<int32_t> light_medium_;
};

}  // namespace foton
