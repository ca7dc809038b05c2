#include "curve_bvh.h"

#include <algorithm>

namespace foton::kern {

CurveBvh::CurveBvh(const std::vector<CurveSegment>& segments, const std::vector<uint8_t>& ribbon,
                   const BvhBuildParams::ParallelInvoke& parallel, int split) {
    const uint32_t parts = 1u << std::clamp(split, 0, 6);
    part_du_ = 1.f / float(parts);
    std::vector<CurveSegment> all;
    std::vector<uint32_t> owner;
    std::vector<float> u0;
    all.reserve(segments.size() * parts);
    for (std::size_t i = 0; i < segments.size(); ++i)
        for (uint32_t k = 0; k < parts; ++k) {
            const float a = float(k) / float(parts), b = float(k + 1) / float(parts);
            all.push_back(parts == 1 ? segments[i] : curve_part(segments[i], a, b));
            owner.push_back(uint32_t(i));
            u0.push_back(a);
        }
    std::vector<PrimRef> boxes(all.size());
    for (std::size_t i = 0; i < all.size(); ++i) {
        curve_bounds(all[i], boxes[i].lo, boxes[i].hi);
        boxes[i].id = uint32_t(i);
        boxes[i].pad = 0;
    }
    BvhBuildParams p;
    p.leaf_block = 1;
    p.max_leaf = 4;
    p.parallel = parallel;
    bvh_ = build_binary_bvh(boxes, p);
    // Parts in leaf order, so a leaf's tests read consecutive memory.
    segments_.reserve(bvh_.prims.size());
    for (std::size_t i = 0; i < bvh_.prims.size(); ++i) {
        const uint32_t part = bvh_.prims[i];
        segments_.push_back(all[part]);
        ids_.push_back(owner[part]);
        u0_.push_back(u0[part]);
        ribbon_.push_back(ribbon[owner[part]]);
        bvh_.prims[i] = uint32_t(i);
    }
}

bool CurveBvh::closest(const Ray1& ray, CurveHit& hit, uint32_t& id, uint64_t& tests) const {
    uint32_t best = UINT32_MAX;
    hit.t = std::min(hit.t, ray.tmax);
    const CurveRay cr(ray);
    walk_binary_bvh(
        bvh_, ray, [&] { return hit.t; },
        [&](uint32_t i) {
            ++tests;
            if (intersect_curve(cr, segments_[i], ribbon_[i] != 0, hit)) best = i;
            return false;
        });
    if (best == UINT32_MAX) return false;
    hit.u = u0_[best] + part_du_ * hit.u;
    id = ids_[best];
    return true;
}

bool CurveBvh::any(const Ray1& ray, uint64_t& tests) const {
    bool found = false;
    const CurveRay cr(ray);
    walk_binary_bvh(
        bvh_, ray, [&] { return ray.tmax; },
        [&](uint32_t i) {
            ++tests;
            found = occluded_curve(cr, segments_[i], ribbon_[i] != 0);
            return found;
        });
    return found;
}

std::size_t CurveBvh::memory_bytes() const {
    return bvh_.used * sizeof(BinaryNode) + bvh_.prims.size() * sizeof(uint32_t) +
           segments_.size() * (sizeof(CurveSegment) + sizeof(uint32_t) + sizeof(float) + 1);
}

}  // namespace foton::kern
