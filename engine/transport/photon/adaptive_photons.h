#pragma once
// Adaptive photon tracing (Hachisuka and Jensen 2011, "Robust adaptive photon tracing using
// photon path visibility"; the photon-mapping thesis' future work, 8.1.1) for SPPM and PPM.
// A photon path is visible when one of its photons (not the first, direct, hit, which next
// event estimation stands for) lands within the radius of a visible point of the pass.
// Photons are sampled by Markov chains over their primary sample vectors whose stationary
// density is that visibility: every step first proposes a fresh uniform vector (the chain
// jumps to it when it is visible: replica exchange with the uniform sampler), and otherwise a
// mutation of the current vector, each number moved by up to +-delta (wrapping around),
// accepted when visible; delta adapts towards a 23.4 % acceptance rate. Each step stores the
// chain's current path. The pass's uniform proposals estimate the visible fraction Z of all
// paths, and every stored path carries Z / (the pass's chain steps that stored a path) of its
// light's power, so the map estimates the flux uniform photons would where it matters, with
// the photons there.
//
// Chains live in fixed chunks (256 chains, 16 steps each, per 4096 photons of a pass) kept
// across passes and numbered by chunk, so the map is the same for any thread count and MPI
// ranks own whole chunks. At the start of a pass every chain's path is traced again and
// dropped when the new visible points no longer see it.
#include <cstdint>
#include <vector>

#include "engine/core/math.h"
#include "engine/transport/photon/photon_tracer.h"
#include "engine/transport/photon/sppm_visible.h"

namespace foton {

// The visible points of a pass in a hash grid of cells at least as large as the largest
// radius: is a point within the radius of any of them?
class VisiblePointGrid {
  public:
    void build(const std::vector<SppmPixel>& pixels);
    bool sees(const Vec3& p) const;
    bool empty() const { return keys_.empty(); }

  private:
    uint64_t key(int64_t x, int64_t y, int64_t z) const;
    int64_t cell(float v, float lo) const;
    struct Point {
        float x, y, z, r2;
    };
    float cell_ = 1.f;
    Vec3 lo_;
    std::vector<uint64_t> keys_;  // sorted, one per point
    std::vector<Point> points_;   // in key order
};

struct AdaptiveChain {
    std::vector<float> u;  // the current primary sample vector (empty: no visible path yet)
    float delta = 0.25f;   // the mutation's reach
    uint64_t mutations = 0;
    PhotonMap photons;  // the current path's photons, full power
};

struct AdaptiveStats {
    uint64_t uniform = 0, uniform_visible = 0;
    uint64_t mutations = 0, accepted = 0;
    uint64_t recorded = 0;  // chain steps that stored a path
};

class AdaptivePhotonTracer {
  public:
    AdaptivePhotonTracer(const PhotonTracer& tracer, uint64_t seed, uint32_t max_depth,
                         bool unscaled_roulette);
    // A pass's `emitted` photon paths (rounded up to whole chunks), stored in chunk order.
    PhotonMap run(uint64_t pass, uint64_t emitted, const VisiblePointGrid& visible,
                  RenderStats& stats, const std::atomic<bool>* cancel, const Cluster* cluster);
    const AdaptiveStats& totals() const { return totals_; }

    static constexpr uint32_t kChains = 256, kSteps = 16;

  private:
    // Traces `count` paths of numbers[k * dims_ ...] into `out`, with each stored photon's
    // path in `by`; visible[k]: path k is visible.
    void trace_paths(uint64_t pass, const std::vector<float>& numbers, uint32_t count,
                     const VisiblePointGrid& grid, PhotonWorkspace& ws, PhotonMap& out,
                     std::vector<uint32_t>& by, std::vector<uint8_t>& visible,
                     RenderStats& stats) const;
    // A chunk's steps: its chains' paths, each stored at full power once per step it holds it.
    void run_chunk(uint64_t pass, std::size_t chunk, const VisiblePointGrid& grid,
                   PhotonWorkspace& ws, PhotonMap& out, AdaptiveStats& st, RenderStats& stats);

    const PhotonTracer& tracer_;
    uint64_t seed_;
    uint32_t max_depth_, dims_;
    bool unscaled_;
    std::vector<std::vector<AdaptiveChain>> chunks_;  // kept across passes
    AdaptiveStats totals_;
};

}  // namespace foton
