#pragma once
// What the stages of a bidirectional iteration share: the scene and its lights, the settings,
// and the iteration's constants (number of light paths, merge radius, MIS weights).
#include <cstdint>
#include <vector>

#include "engine/accel/intersector.h"
#include "engine/core/rng_streams.h"
#include "engine/scene/light_set.h"
#include "engine/transport/common/kernel_materials.h"
#include "engine/transport/common/primary_vector.h"
#include "engine/transport/run/render_settings.h"
#include "strategy_layers.h"
#include "vcm_mis.h"

namespace foton {

// The random streams of the bidirectional integrators.

struct VcmContext {
    const Scene& scene;
    const RenderSettings& settings;
    const Intersector& accel;
    const LightSet& lights;
    uint64_t seed = 0;
    uint32_t max_segments = 9;  // max_depth scattering vertices + 1
    // Per iteration.
    uint64_t iteration = 0;
    // The iteration's place in its pass (sample i of n): the pixel positions of a pass's
    // iterations are one pattern of the renderer's sampler, stratified across iterations.
    uint32_t pass = 0, pass_sample = 0, pass_samples = 1;
    uint32_t light_paths = 0;  // N: one per pixel of the film
    float radius = 0.f;        // merge radius
    VcmWeights weights;
    // The materials whose joins go through the lobe-pair kernel (null or not enabled: none).
    const KernelMaterials* kernels = nullptr;
    // Per-strategy images (off unless strategy_images is set).
    StrategyLayers layers;
    // Participating media (subpath_media.h): whether the scene has them, and each emitter's
    // medium, where its light paths start.
    bool media = false;
    const std::vector<int32_t>* light_medium = nullptr;
    // Metropolis light transport over bidirectional paths (mlt_paths="bdpt"): camera path i
    // and light path i of the batch read their numbers from primary[i] (the camera path's
    // film position and lens first, then the two subpaths' numbers interleaved:
    // primary_camera_dim, primary_light_dim) instead of counter-based streams; null: not.
    PrimaryVector* const* primary = nullptr;
};

// Where a bidirectional sample's numbers lie in its primary vector: the film position (2)
// and lens (2), then camera number d and light number d side by side, so that a mutation
// that lengthens one subpath leaves the other's numbers where they were.
inline constexpr uint32_t kPrimaryBidirStart = 4;
inline uint32_t primary_camera_dim(uint32_t d) {
    return kPrimaryBidirStart + 2 * d;
}
inline uint32_t primary_light_dim(uint32_t d) {
    return kPrimaryBidirStart + 2 * d + 1;
}

}  // namespace foton
