#pragma once
// The first pass of photon mapping: emit photons from the lights in proportion to their
// power, trace them through the scene as SoA ray batches, and store them at non-specular
// hits (the thesis' chapter 5.3).
//
// Photon i of a pass is a pure function of (seed, pass, i): its light, its emitted ray
// (stratified: the direction comes from a randomly shifted Hammersley point set over the
// pass's photons) and every bounce. A chunk of consecutive photons is traced as one
// wavefront into its own buffers; the chunks are concatenated in order, so the maps are the
// same for any thread count.
//
// At a hit the photon is stored if the BSDF has a non-delta part; then it survives with
// probability q = min(1, max channel of f cos / pdf) of the sampled direction (Russian
// roulette on reflect/absorb from the surface's albedo) and its power is scaled by
// (f cos / pdf) / q, which keeps the estimate unbiased; `unscaled` keeps the power as it is
// (the thesis' simpler, biased variant for coloured surfaces).
#include <atomic>
#include <cstdint>
#include <vector>

#include "engine/accel/intersector.h"
#include "engine/core/progress.h"
#include "engine/core/ray_batch.h"
#include "engine/core/stats.h"
#include "engine/scene/light_set.h"
#include "engine/transport/photon/importon_map.h"
#include "engine/transport/photon/photon_map.h"

namespace foton {

enum class PhotonMapKind : uint8_t {
    Global,   // every non-specular hit (direct, indirect and caustic photons)
    Caustic,  // only photons whose path is L S+ D: at least one delta bounce, nothing else
};

struct PhotonPassSettings {
    PhotonMapKind kind = PhotonMapKind::Global;
    uint64_t emitted = 100000;  // photons emitted (each carries 1/emitted of the flux)
    uint32_t max_depth = 8;     // bounces a photon may make
    bool unscaled_roulette = false;
    uint64_t pass = 0;  // distinguishes the random numbers of passes (PPM)
    // Global pass: continue every photon's line through its first hit and store a shadow
    // photon (light id, negated power) at each further surface it crosses (Jensen 1995).
    bool shadow_photons = false;
    // The render's cancel flag (RenderOptions::cancel): once set, the pass traces no further
    // chunk and ends with the photons traced so far.
    const std::atomic<bool>* cancel = nullptr;
    // Visual importance (importon_map.h): a photon is stored with the map's probability q at
    // its position and its power divided by q. Null: every photon is stored.
    const ImportonMap* importance = nullptr;
    // Adaptive photon tracing (adaptive_photons.h): photon k of a trace call takes its random
    // numbers from numbers[k * number_dims + dim] (its primary sample vector; the emitted
    // direction from dims 4-5, not the pass's Hammersley set) and carries its light's whole
    // power (emitted is ignored); stored_by[j] says which photon stored photon j of `out`.
    const float* numbers = nullptr;
    uint32_t number_dims = 0;
    std::vector<uint32_t>* stored_by = nullptr;
};

// A photon's random dimensions: light choice, position (2), triangle, direction (2), then per
// bounce the BSDF lobe and direction (3) and Russian roulette.
inline constexpr uint32_t kPhotonDimLight = 0, kPhotonDimPos = 1, kPhotonDimTriangle = 3,
                          kPhotonDimDirection = 4, kPhotonDimFirstBounce = 8,
                          kPhotonDimsPerBounce = 4;
inline uint32_t photon_dims(uint32_t max_depth) {
    return kPhotonDimFirstBounce + kPhotonDimsPerBounce * max_depth;
}

// Shadow photons' lines (Jensen 1995), traced as a batch after the first hits of a chunk.
struct ShadowLineWork {
    struct Crossing {
        uint32_t line;
        Vec3 p, ng, dir;
    };
    RayBatch rays, next;
    HitBatch hits;
    std::vector<RGB> power;       // per line: the photon's power at its first hit
    std::vector<uint16_t> light;  // per line: its emitter
    std::vector<Crossing> found;  // the surfaces the lines cross that take photons
    void clear() {
        rays.clear();
        power.clear();
        light.clear();
        found.clear();
    }
};

struct PhotonWorkspace {
    ShadowLineWork shadow;
    RayBatch rays, next;
    HitBatch hits;
    std::vector<RGB> power;
    std::vector<uint8_t> specular_only;  // path so far: light followed by delta bounces only
    std::vector<uint8_t> last_specular;  // its last bounce was off a delta lobe
    std::vector<uint16_t> light;         // emitter of each photon
};

class PhotonTracer {
  public:
    PhotonTracer(const Scene& scene, const Intersector& accel, const LightSet& lights,
                 uint64_t seed);
    // Traces photons [first, first + count) of the pass and stores them into `out`.
    void trace(const PhotonPassSettings& s, uint64_t first, uint32_t count, PhotonWorkspace& ws,
               PhotonMap& out, PhotonMap* shadow, RenderStats& stats) const;
    // The whole pass on the calling arena's threads, chunks concatenated in order; shadow
    // photons (s.shadow_photons) go to `shadow`; `task` counts the photons emitted.
    // Across the MPI ranks of `cluster`, each traces a contiguous share of the chunks and
    // every rank gets the whole map, the shares concatenated in rank order (chunk order).
    PhotonMap run(const PhotonPassSettings& s, RenderStats& stats, PhotonMap* shadow = nullptr,
                  const ProgressTask* task = nullptr, const Cluster* cluster = nullptr) const;

  private:
    float rand(uint64_t pass, uint64_t photon, uint32_t dim) const;
    // Photon `slot` of a trace call's number `dim`: the pass's stream, or s.numbers.
    float number(const PhotonPassSettings& s, uint64_t first, uint32_t slot, uint32_t dim) const {
        return s.numbers ? s.numbers[std::size_t(slot) * s.number_dims + dim]
                         : rand(s.pass, first + slot, dim);
    }
    // Follows every queued line through up to kShadowCrossings further surfaces and stores a
    // shadow photon at each that takes photons, line after line as a photon-by-photon walk
    // would (so the map, and the image, do not depend on the batching).
    void trace_shadow_lines(ShadowLineWork& w, PhotonMap& shadow, RenderStats& stats) const;

    const Scene& scene_;
    const Intersector& accel_;
    const LightSet& lights_;
    uint64_t seed_;
};

}  // namespace foton
