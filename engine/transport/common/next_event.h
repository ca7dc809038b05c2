#pragma once
// Next event estimation, written once for every integrator. sample_light weighs a light
// sample against BSDF sampling by MIS (the path tracer); sample_direct gives it full weight,
// for vertices whose BSDF is not sampled onwards (a final-gather or photon visible point, a
// cache record's hit, a path vertex whose indirect light comes from the cache), where the
// light sample is the only estimator of direct light.
#include <cmath>

#include "engine/core/ray_batch.h"
#include "engine/core/warp.h"
#include "engine/scene/light_set.h"
#include "engine/scene/material.h"
#include "engine/transport/common/surface.h"
#include "mis.h"

namespace foton {

struct DirectSample {
    uint32_t light = 0;
    Vec3 origin, dir;  // the shadow ray that decides it
    float tmax = 0.f;
    RGB value;  // the contribution if the shadow ray is unoccluded
};

// Next event estimation, the one version every integrator uses: a sample of light `li`
// (picked with probability `pick`; u and uc choose the point on it) lighting the `lobes` of
// `bsdf` at sp, carrying weight * f * Li * |cos| * w * scale / (pick * pdf), where w is the
// MIS weight against BSDF sampling under `mis` (None: full weight; delta lights always take
// full weight). False when the sample adds nothing.
inline bool sample_light(const LightSet& lights, uint32_t li, float pick, const SurfacePoint& sp,
                         const Bsdf& bsdf, const BsdfContext& ctx, const Vec3& wo,
                         const warp::Frame& frame, const RGB& weight, Point2 u, float uc,
                         uint8_t lobes, MisHeuristic mis, float scale, DirectSample& out) {
    LightSample ls;
    if (!lights.sample_li(li, sp.p, u, uc, ls) || dot(ls.wi, sp.ng) <= 0.f) return false;
    const Vec3 wi = frame.to_local(ls.wi);
    const RGB f = bsdf.f_restricted(wo, wi, ctx, lobes);
    if (f.is_black()) return false;
    const float pl = pick * ls.pdf;
    const bool full = mis == MisHeuristic::None || lights.emitter(li).is_delta();
    const float w = full ? 1.f : mis_weight(mis, pl, bsdf.pdf(wo, wi, ctx));
    out.light = li;
    out.value = weight * f * ls.Li * (std::fabs(wi.z) * w * scale / pl);
    if (out.value.is_black()) return false;
    out.origin = offset_origin(sp, ls.wi);
    out.dir = ls.wi;
    out.tmax = std::isinf(ls.dist) ? kInfinity : ls.dist * (1.f - 1e-4f) - sp.epsilon;
    return true;
}

// One light sample for the non-delta lobes, without multiple importance sampling: for
// vertices whose BSDF is not sampled onwards (see the top of this file). u_pick chooses the
// light.
inline bool sample_direct(const LightSet& lights, const SurfacePoint& sp, const Bsdf& bsdf,
                          const Vec3& wo, const warp::Frame& frame, const RGB& weight, float u_pick,
                          Point2 u, float uc, DirectSample& out) {
    if (lights.empty()) return false;
    float pick;
    const uint32_t li = lights.select(u_pick, pick);
    const BsdfContext ctx{sp.front_face, Transport::Radiance};
    return sample_light(lights, li, pick, sp, bsdf, ctx, wo, frame, weight, u, uc,
                        kDiffuse | kGlossy, MisHeuristic::None, 1.f, out);
}

inline void queue_direct(const DirectSample& ds, uint32_t slot, RayBatch& shadow,
                         std::vector<RGB>& shadow_value) {
    shadow.push(ds.origin, ds.dir, 0.f, ds.tmax, slot);
    shadow_value.push_back(ds.value);
}

}  // namespace foton
