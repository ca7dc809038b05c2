#pragma once
// One light sample for the non-delta lobes at a surface point, without multiple importance
// sampling: for vertices whose BSDF is not sampled onwards (a final-gather or photon visible
// point, a cache record's hit, a path vertex whose indirect light comes from the cache), the
// light sample is the only estimator of direct light and takes full weight.
#include <cmath>

#include "engine/core/ray_batch.h"
#include "engine/core/warp.h"
#include "engine/scene/light_set.h"
#include "engine/scene/material.h"
#include "engine/transport/common/surface.h"

namespace foton {

struct DirectSample {
    uint32_t light = 0;
    Vec3 origin, dir;  // the shadow ray that decides it
    float tmax = 0.f;
    RGB value;  // the contribution if the shadow ray is unoccluded
};

// u_pick chooses the light, u and uc the point on it. False when the sample adds nothing.
inline bool sample_direct(const LightSet& lights, const SurfacePoint& sp, const Bsdf& bsdf,
                          const Vec3& wo, const warp::Frame& frame, const RGB& weight, float u_pick,
                          Point2 u, float uc, DirectSample& out) {
    if (lights.empty()) return false;
    float pick;
    out.light = lights.select(u_pick, pick);
    LightSample ls;
    if (!lights.sample_li(out.light, sp.p, u, uc, ls) || dot(ls.wi, sp.ng) <= 0.f) return false;
    const Vec3 wi = frame.to_local(ls.wi);
    const BsdfContext ctx{sp.front_face, Transport::Radiance};
    const RGB f = bsdf.f_restricted(wo, wi, ctx, kDiffuse | kGlossy);
    out.value = weight * f * ls.Li * (std::fabs(wi.z) / (pick * ls.pdf));
    if (out.value.is_black()) return false;
    out.origin = offset_origin(sp, ls.wi);
    out.dir = ls.wi;
    out.tmax = std::isinf(ls.dist) ? kInfinity : ls.dist * (1.f - 1e-4f) - sp.epsilon;
    return true;
}

inline void queue_direct(const DirectSample& ds, uint32_t slot, RayBatch& shadow,
                         std::vector<RGB>& shadow_value) {
    shadow.push(ds.origin, ds.dir, 0.f, ds.tmax, slot);
    shadow_value.push_back(ds.value);
}

}  // namespace foton
