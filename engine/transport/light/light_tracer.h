#pragma once
// Light tracing (the photon-mapping thesis, chapter 4.3): paths start at the lights, chosen
// by power, and every vertex with a non-delta BSDF (and the emitting point itself) is joined
// to the pinhole by a shadow ray; what arrives is splatted onto the pixel it projects to.
// The transport is adjoint (importance): dielectric refraction is not scaled by eta^2 and
// shading normals get Veach's correction.
//
// Determinism: paths are numbered; a chunk of consecutive paths is traced as one wavefront
// and returns its splats in path order; the driver adds the chunks' splats to the film in
// chunk order, so the sum is the same whatever thread traced which chunk.
#include <cstdint>
#include <vector>

#include "engine/accel/intersector.h"
#include "engine/core/ray_batch.h"
#include "engine/core/stats.h"
#include "engine/core/warp.h"
#include "engine/film/pixel_sums.h"
#include "engine/scene/light_set.h"
#include "engine/transport/common/kernel_materials.h"
#include "engine/transport/common/wavefront.h"
#include "engine/transport/run/render_context.h"

namespace foton {

// The light paths' random dimensions: light choice, position (2), direction (2), triangle;
// then per bounce the BSDF lobe and direction (3) and Russian roulette.
inline constexpr uint32_t kLightDimFirstBounce = 8, kLightDimsPerBounce = 4;

struct LightTracerWorkspace : WavefrontBuffers {
    std::vector<FilmPoint> shadow_at;  // where on the film each shadow ray's splat lands
    // A bounce's hits the importance kernel shades (batch entries), by glossy kind first so
    // that a register's lanes mostly run one lobe's code, and their lanes.
    std::vector<uint32_t> kernel_groups[kKernelGroups], kernel_entries;
    KernelLanes lanes;
};

// What a connection from p (unit direction wc to the pinhole eye at distance dist) carrying
// `value` adds, and where on the film (the pixel filter spreads it from there); false when p
// projects off the film or nothing arrives.
bool splat_on_film(const Scene& scene, const Vec3& p, const Vec3& wc, float dist, const RGB& value,
                   FilmPoint& at, RGB& splat);

// A light path's emitting point seen from the eye along wc (unit, from the point towards the
// eye): what it sends there, es.Le cos / (pmf pdf_pos), and the shadow ray's origin pushed off
// the emitter on the eye's side. False for delta and infinite lights and points facing away.
bool emitting_point_to_eye(const Emitter& em, const EmittedRay& er, const Vec3& wc, RGB& value,
                           Vec3& origin);

// A light path's continuation from a surface vertex: the BSDF sampled from u0 and u12 for
// importance (BsdfContext ctx), beta times f |cos| / pdf with Veach's adjoint factor adj
// (|wo.ns| / |wo.ng|). False when the sample fails, leaves on the wrong side of the true
// surface (normal ng) or carries nothing.
bool continue_light_path(const Bsdf& bsdf, const warp::Frame& frame, const Vec3& wo,
                         const BsdfContext& ctx, const Vec3& ng, float adj, float u0, Point2 u12,
                         RGB& beta, Vec3& wi);

class LightTracer {
  public:
    explicit LightTracer(const RenderContext& ctx);
    // Traces paths [first, first + count) and appends their (unoccluded) splats. A splat's
    // value is one path's contribution: the pixel estimate is the splat sum over the number
    // of paths traced.
    void trace(uint64_t first, uint32_t count, LightTracerWorkspace& ws, std::vector<Splat>& splats,
               RenderStats& stats) const;

  private:
    float rand(uint64_t path, uint32_t dim) const;
    // What a connection from p (unit direction wc to the eye at distance dist) carrying
    // `value` adds, and where on the film; false when p projects off the film or nothing
    // arrives.
    bool to_film(const Vec3& p, const Vec3& wc, float dist, const RGB& value, FilmPoint& at,
                 RGB& splat) const;
    // The scalar vertex of a hit (light_tracer.cpp) and the kernel's lanes (light_lanes.cpp):
    // the connection to the eye into the shadow batch, the continuation into `next`.
    void shade_vertex(uint64_t first, uint32_t depth, std::size_t i,
                      LightTracerWorkspace& ws) const;
    void shade_lanes(uint64_t first, uint32_t depth, LightTracerWorkspace& ws) const;
    void push_connection(const Vec3& o, const Vec3& wc, float tmax, const RGB& splat, FilmPoint at,
                         uint32_t slot, LightTracerWorkspace& ws) const;

    const RenderContext ctx_;
    const KernelMaterials kernels_;  // enabled: the settings let the kernel shade
};

}  // namespace foton
