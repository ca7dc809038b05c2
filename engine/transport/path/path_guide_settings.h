#pragma once
// The settings of photon-guided path tracing (path_guide.h): renderer keys guided,
// guide_emitted, guide_cells, guide_min_photons and guide_fraction.
#include <cstdint>

#include "engine/core/params.h"
#include "engine/transport/common/transport_settings.h"

namespace foton {

// The guide's voxels along the scene's longest side, at most (its dense index holds
// (129^3 x 6) slots then).
inline constexpr uint32_t kMaxGuideCells = 128;

struct PathGuideSettings {
    bool enabled = false;
    uint64_t emitted = 1000000;  // photons emitted by the guide's pre-pass
    uint32_t cells = 24;         // voxels along the scene's longest side
    uint32_t min_photons = 8;    // a bin with fewer photons does not guide
    float fraction = 0.5f;       // probability of drawing a direction from the guide
};

// The guide's keys, refused without guided=true or for an integrator that cannot be guided.
// Guided paths default to no Russian roulette (`rr_depth` unless the file gives it): roulette
// throws away what the guide bought.
void parse_path_guide_settings(const ParamSet& params, const IntegratorTraits& integrator,
                               PathGuideSettings& settings, uint32_t& rr_depth);

}  // namespace foton
