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
#include "guide_mixture.h"
#include "mis.h"
#include "shading_point.h"

namespace foton {

struct DirectSample {
    uint32_t light = 0;
    Vec3 origin, dir;  // the shadow ray that decides it
    float tmax = 0.f;
    RGB value;  // the contribution if the shadow ray is unoccluded
};

// Which light a sample takes (picked with probability `pick`) and the numbers that place the
// sample on it.
struct LightChoice {
    uint32_t light = 0;
    float pick = 1.f;
    Point2 u;
    float uc = 0.f;
    uint32_t tri = kWholeEmitter;  // under the light BVH, the triangle of a mesh
};

// Next event estimation, the one version every integrator uses: a sample of the chosen
// light lighting the `lobes` of v's BSDF, carrying v.weight * f * Li * |cos| * w * scale /
// (pick * pdf), where w is the MIS weight against BSDF sampling under `mis` (None: full
// weight; delta lights always take full weight). A guided vertex's BSDF strategy is the
// mixture `strategy`, whose density the weight uses. False when the sample adds nothing.
inline bool sample_light(const LightSet& lights, const LightChoice& c, const ShadingPoint& v,
                         uint8_t lobes, const Mis& mis, float scale, DirectSample& out,
                         const GuideMixture& strategy = {}) {
    const SurfacePoint& sp = v.sp;
    LightSample ls;
    if (!lights.sample_li(c.light, sp.p, c.u, c.uc, ls, c.tri) ||
        !v.m.bsdf.side_allowed(ls.wi, sp.ng))
        return false;
    const Vec3 wi = v.frame.to_local(ls.wi);
    const BsdfContext ctx{sp.front_face, Transport::Radiance};
    const RGB f = v.m.bsdf.f_restricted(v.wo, wi, ctx, lobes);
    if (f.is_black()) return false;
    const float pl = c.pick * ls.pdf;
    const bool full = mis.heuristic == MisHeuristic::None || lights.emitter(c.light).is_delta();
    const float w =
        full ? 1.f : mis_weight(mis, pl, strategy.pdf(v.m.bsdf.pdf(v.wo, wi, ctx), ls.wi));
    out.light = c.light;
    const RGB li = v.wavelengths ? v.wavelengths->illuminant(ls.Li) : ls.Li;
    out.value = v.weight * f * li * (std::fabs(wi.z) * w * scale / pl);
    if (out.value.is_black()) return false;
    const ShadowRay ray = shadow_ray_to(sp, ls);
    out.origin = ray.origin;
    out.dir = ray.dir;
    out.tmax = ray.tmax;
    return true;
}

// One light sample for the non-delta lobes, without multiple importance sampling: for
// vertices whose BSDF is not sampled onwards (see the top of this file). u_pick chooses the
// light; the choice goes to `picked` when asked for, also when the sample then fails (a
// control variate needs it: direct_control_variate.h).
inline bool sample_direct(const LightSet& lights, const ShadingPoint& v, float u_pick, Point2 u,
                          float uc, DirectSample& out, LightPick* picked = nullptr) {
    if (lights.empty()) return false;
    LightPick pick;
    if (!lights.pick(u_pick, v.sp.p, v.sp.ng, pick)) return false;
    if (picked) *picked = pick;
    LightChoice c;
    c.light = pick.light;
    c.pick = pick.pmf;
    c.tri = pick.tri;
    c.u = u;
    c.uc = uc;
    return sample_light(lights, c, v, kDiffuse | kGlossy, Mis{MisHeuristic::None}, 1.f, out);
}

inline void queue_direct(const DirectSample& ds, uint32_t slot, RayBatch& shadow,
                         std::vector<RGB>& shadow_value) {
    shadow.push(ds.origin, ds.dir, 0.f, ds.tmax, slot);
    shadow_value.push_back(ds.value);
}

}  // namespace foton
