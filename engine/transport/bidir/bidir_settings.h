#pragma once
// The settings of bdpt, bpm and vcm (transport/bidir). `strategy="s,t"` keeps only the
// strategy with s light and t camera vertices, at full weight (a debug switch: each strategy
// alone converges to its share of the image); the default, all strategies, weighted.
// `merge_index="grid|kdtree"` (bpm, vcm): the light vertices' index for merging, a hashed grid
// of cells 2r wide (default) or the photon map's kd-tree kernel. `strategy_images=L` (2 to
// 12): what each strategy of paths up to L vertices adds, as AOV layers (strategy_layers.h).
#include <cstdint>

#include "engine/core/params.h"
#include "engine/transport/common/transport_settings.h"

namespace foton {

enum class MergeIndex : uint8_t { Grid, KdTree };
struct BidirSettings {
    int only_s = -1, only_t = -1;
    MergeIndex merge_index = MergeIndex::Grid;
    // strategy_images=L: each strategy of paths up to L vertices as a layer (strategy_layers.h);
    // 0: none.
    uint32_t strategy_images = 0;
};

// The bidirectional keys (strategy, merge_index) and the rules the family sets on the shared
// ones (mis, rr_depth). Keys for other integrators (mis=max, rr_depth; strategy or merge_index
// under another integrator) are warnings at their line and ignored (mis becomes power); a bad
// value is an error at its line.
void parse_bidir_settings(const ParamSet& params, const IntegratorTraits& integrator,
                          MisHeuristic& mis, BidirSettings& settings);

}  // namespace foton
