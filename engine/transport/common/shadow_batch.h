#pragma once
// The occlusion stage shared by the camera wavefronts: a batch of shadow rays, each carrying
// the radiance it adds to its slot if nothing blocks it, tested at once.
#include <vector>

#include "engine/accel/intersector.h"
#include "engine/core/ray_batch.h"
#include "engine/core/rgb.h"
#include "engine/core/stats.h"

namespace foton {

inline void resolve_shadow_rays(const Intersector& accel, const RayBatch& shadow,
                                const std::vector<RGB>& value, std::vector<uint8_t>& occluded,
                                std::vector<RGB>& radiance, RenderStats& stats, StageClock& clock) {
    if (shadow.empty()) return;
    accel.occluded(shadow, occluded, stats.trace);
    for (std::size_t i = 0; i < shadow.size(); ++i)
        if (!occluded[i]) radiance[shadow.id[i]] += value[i];
    stats.shadow_rays += shadow.size();
    stats.add(Stage::Occlusion, shadow.size(), clock);
}

}  // namespace foton
