// shade_specular at SIMD width: the twin's branches (mirror or dielectric, reflection or
// refraction, the Fresnel kinds) computed on every lane and selected.
#include <limits>

#include "shade_lanes.h"
#include "specular_shade.h"

namespace foton::kern {

namespace {

using namespace lanes;

void specular_lanes(const Lanes& l, bool roulette) {
    reconstruct_surface(l);
    const FloatV zero(0.f), one(1.f);
    const V3 p = l.in3(kDvPx), ng = l.in3(kDvNgx), ns = l.in3(kDvNsx);
    const V3 beta = l.in3(kDvBetaR), color = l.in3(kDvSpecR);
    V3 s, t;
    shading_frame(ns, s, t);
    const V3 wo_world = l.in3(kDvWox);
    const V3 wo{dot(wo_world, s), dot(wo_world, t), dot(wo_world, ns)};
    const V3 mirror{neg(wo.x), neg(wo.y), wo.z};

    const MaskV is_mirror = l.in(kDvSpecKind) == one;
    // A mirror: its Fresnel term at the reflected direction's cosine (each kind computed only
    // when a lane has it).
    const FloatV c = xsimd::abs(mirror.z);
    const FloatV fresnel = l.in(kDvFresnel);
    V3 fr{one, one, one};
    if (xsimd::any(fresnel == FloatV(2.f))) {
        const FloatV fd = fresnel_dielectric(c, one, l.in(kDvIor));
        fr = select(fresnel == FloatV(2.f), V3{fd, fd, fd}, fr);
    }
    if (xsimd::any(fresnel == one)) {
        const V3 fc{fresnel_conductor(c, l.in(kDvEtaR), l.in(kDvKR)),
                    fresnel_conductor(c, l.in(kDvEtaG), l.in(kDvKG)),
                    fresnel_conductor(c, l.in(kDvEtaB), l.in(kDvKB))};
        fr = select(fresnel == one, fc, fr);
    }
    const FloatV inv = one / c;
    const V3 f_mirror{color.x * fr.x * inv, color.y * fr.y * inv, color.z * fr.z * inv};

    // A dielectric: reflection or refraction by its Fresnel term. A chunk of mirrors skips it
    // (reflect everywhere: no lane refracts).
    MaskV reflect = one == one;
    FloatV F = one, eta_ratio = one;
    V3 tr = mirror, f_dielectric{zero, zero, zero};
    if (!xsimd::all(is_mirror)) {
        const MaskV front = l.in(kDvFront) != zero;
        const FloatV ior = l.in(kDvIor);
        const FloatV eta_i = xsimd::select(front, one, ior);
        const FloatV eta_t = xsimd::select(front, ior, one);
        F = fresnel_dielectric(c, eta_i, eta_t);
        const V3 nrm{zero, zero, xsimd::select(wo.z > zero, one, FloatV(-1.f))};
        const V3 d = neg(wo);
        const FloatV e = eta_i / eta_t;
        const FloatV ci = neg(dot(d, nrm));
        const FloatV k = one - e * e * (one - ci * ci);
        tr = d * e + nrm * (e * ci - simd::vsqrt(k));
        tr = tr * (one / simd::vsqrt(dot(tr, tr)));
        const FloatV w = l.in(kDvLobeWeight);
        // std::clamp(u w / w, 0, the float below 1).
        const FloatV below_one(0x1.fffffep-1f), uw = (l.in(kDvUChoice)*w) / w;
        const FloatV uc =
            xsimd::select(uw < zero, zero, xsimd::select(below_one < uw, below_one, uw));
        reflect = (uc < F) | (k < zero);
        const FloatV k_r = F / c;
        const FloatV k_t = (one - F) * ((eta_i * eta_i) / (eta_t * eta_t)) / xsimd::abs(tr.z);
        f_dielectric = select(reflect, color * k_r, l.in3(kDvTransR) * k_t);
        eta_ratio = eta_t / eta_i;
    }

    const MaskV transmit = ~(is_mirror | reflect);
    const V3 wi = select(transmit, tr, mirror);
    const V3 f = select(is_mirror, f_mirror, f_dielectric);
    const FloatV pdf = xsimd::select(is_mirror, one, xsimd::select(reflect, F, one - F));
    const FloatV eta = xsimd::select(transmit, eta_ratio, one);
    MaskV ok = c != zero;
    ok = ok & (pdf > zero);
    const V3 w_world = s * wi.x + t * wi.y + ns * wi.z;
    const FloatV side = dot(w_world, ng);
    ok = ok & ((transmit & (side < zero)) | (~transmit & (side > zero)));
    const FloatV kn = xsimd::abs(wi.z) / pdf;
    V3 nb{beta.x * (f.x * kn), beta.y * (f.y * kn), beta.z * (f.z * kn)};
    ok = ok & ((nb.x != zero) | (nb.y != zero) | (nb.z != zero));
    const FloatV es = l.in(kDvEtaScale) * (eta * eta);
    if (roulette) {
        const FloatV q = simd::vmin(max3(nb.x, nb.y, nb.z) * es, one);
        ok = ok & (l.in(kDvURoulette) < q);
        nb = nb * (one / q);
    }
    l.out(kDvShadowValid, zero);
    l.out(kDvNextValid, xsimd::select(ok, one, zero));
    l.out3(kDvNox, offset(p, ng, l.in(kDvEps), w_world));
    l.out3(kDvNdx, w_world);
    l.out3(kDvNbetaR, nb);
    l.out(kDvNpdf, pdf);
    l.out(kDvNetaScale, es);
    l.out(kDvNtransmit, xsimd::select(transmit, one, zero));
}

}  // namespace

void shade_specular(const ShadeTable& v, std::size_t n, bool roulette) {
    for (std::size_t i = 0; i < n; i += simd::kWidth) specular_lanes(Lanes{v, i}, roulette);
}

}  // namespace foton::kern
