#pragma once
// The box of a scene object as a primitive reference of a binary BVH, padded: a sphere
// test's or a transformed ray's rounding may put a hit just outside the exact box.
#include <algorithm>
#include <cmath>

#include "engine/scene/scene.h"
#include "kernels/bvh_build.h"

namespace foton {

inline kern::PrimRef padded_object_ref(const Scene& scene, uint32_t geom) {
    const Bounds3 b = scene.object_bounds(geom);
    const Vec3 e = b.diagonal();
    const float pad = 1e-5f * (std::max({std::fabs(b.lo.x), std::fabs(b.lo.y), std::fabs(b.lo.z),
                                         std::fabs(b.hi.x), std::fabs(b.hi.y), std::fabs(b.hi.z)}) +
                               std::max({e.x, e.y, e.z}));
    kern::PrimRef r;
    for (int a = 0; a < 3; ++a) r.lo[a] = b.lo[a] - pad, r.hi[a] = b.hi[a] + pad;
    r.id = geom;
    r.pad = 0;
    return r;
}

}  // namespace foton
