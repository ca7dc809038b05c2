#pragma once
// Whitted ray tracing (the first thesis) as a wavefront: per tile, camera rays are generated
// into a RayBatch, intersected, shaded into a batch of shadow rays (with the contribution
// each carries if unoccluded) and a batch of reflected/refracted rays (with their path
// weights), the shadow rays are tested, and the loop repeats on the secondary batch until
// it is empty, the depth limit is reached, or every weight falls below the cut-off.
#include "engine/core/aligned.h"
#include "engine/core/ray_batch.h"
#include "engine/core/rgb.h"
#include "render.h"
#include "surface.h"

namespace foton {

// Per-thread scratch reused from tile to tile.
struct WhittedWorkspace {
    RayBatch rays, next, shadow;
    HitBatch hits;
    std::vector<RGB> weight, next_weight, shadow_value;
    std::vector<uint8_t> occluded;
    std::vector<RGB> radiance;  // per pixel sample of the tile
};

class WhittedIntegrator {
  public:
    WhittedIntegrator(const Scene& scene, const Intersector& accel, const RenderOptions& options);
    // Renders one tile into `film` (only the tile's pixels are written).
    void render_tile(const Tile& tile, Film& film, WhittedWorkspace& ws, RenderStats& stats) const;

  private:
    void generate(const Tile& tile, WhittedWorkspace& ws) const;
    void shade(uint32_t depth, const Tile& tile, WhittedWorkspace& ws) const;
    void direct_light(const SurfacePoint& sp, const Material& m, const Vec3& wo, const RGB& weight,
                      uint32_t slot, uint64_t sample_index, uint32_t depth,
                      WhittedWorkspace& ws) const;
    uint64_t global_sample(const Tile& tile, uint32_t slot) const;

    const Scene& scene_;
    const Intersector& accel_;
    RenderOptions options_;
};

}  // namespace foton
