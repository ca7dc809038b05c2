// shade_importance at SIMD width: every branch of the scalar twin a select, every lane of a
// register one light-path vertex.
#include "importance_shade.h"

#include "diffuse_lobes.h"

namespace foton::kern {

namespace {

using namespace lanes;

void importance_lanes(const Lanes& l, bool roulette) {
    reconstruct_surface(l);
    const FloatV zero(0.f), one(1.f);
    const V3 p = l.in3(kDvPx), ng = l.in3(kDvNgx), ns = l.in3(kDvNsx);
    const FloatV eps = l.in(kDvEps);
    const V3 beta = l.in3(kDvBetaR);
    V3 s, t;
    shading_frame(ns, s, t);
    const V3 wo_world = l.in3(kDvWox);
    const FloatV wo_z = dot(wo_world, ns);
    const DiffuseLobes lobes(l, V3{dot(wo_world, s), dot(wo_world, t), wo_z});
    // Veach's adjoint factor |wo.ns| / |wo.ng|; a direction in the geometric surface's plane
    // leaves no vertex.
    const FloatV wo_ng = xsimd::abs(dot(wo_world, ng));
    const MaskV live = wo_ng != zero;
    const FloatV adj = xsimd::abs(wo_z) / wo_ng;

    // The connection to the eye.
    const V3 eye = l.in3(kDvLpx);
    const V3 to = eye - p;
    const V3 wc = to * (one / simd::vsqrt(dot(to, to)));
    const FloatV c_ng = dot(wc, ng);
    const V3 fc = lobes.f(V3{dot(wc, s), dot(wc, t), dot(wc, ns)});
    const FloatV kc = adj * c_ng;
    const V3 value{beta.x * fc.x * kc, beta.y * fc.y * kc, beta.z * fc.z * kc};
    const MaskV connect =
        live & (c_ng > zero) & ((value.x != zero) | (value.y != zero) | (value.z != zero));
    const V3 o = offset(p, ng, eps, wc);
    const V3 oe = eye - o;
    l.out(kDvShadowValid, xsimd::select(connect, one, zero));
    l.out3(kDvSvR, select(connect, value, V3{zero, zero, zero}));
    l.out3(kDvSox, o);
    l.out3(kDvSdx, wc);
    l.out(kDvStmax, simd::vsqrt(dot(oe, oe)) * FloatV(1.f - 1e-4f));

    // The continuation.
    const LobeSample smp = sample_lobes(lobes, l);
    const V3 wi = s * smp.wi.x + t * smp.wi.y + ns * smp.wi.z;
    const FloatV side = dot(wi, ng);
    const FloatV kn = adj * xsimd::abs(side) / smp.pdf;
    V3 nb{beta.x * (smp.f.x * kn), beta.y * (smp.f.y * kn), beta.z * (smp.f.z * kn)};
    MaskV next = live & smp.ok & (side > zero);
    next = next & ((nb.x != zero) | (nb.y != zero) | (nb.z != zero));
    if (roulette) {
        const FloatV q = simd::vmin(max3(nb.x, nb.y, nb.z), one);
        next = next & (l.in(kDvURoulette) < q);
        nb = nb * (one / q);
    }
    l.out(kDvNextValid, xsimd::select(next, one, zero));
    l.out3(kDvNox, offset(p, ng, eps, wi));
    l.out3(kDvNdx, wi);
    l.out3(kDvNbetaR, nb);
    l.out(kDvNpdf, smp.pdf);
}

}  // namespace

void shade_importance(const ShadeTable& v, std::size_t n, bool roulette) {
    for (std::size_t i = 0; i < n; i += simd::kWidth) importance_lanes(Lanes{v, i}, roulette);
}

}  // namespace foton::kern
