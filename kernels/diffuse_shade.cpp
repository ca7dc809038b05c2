// shade_diffuse at SIMD width: every branch of the scalar twin becomes a select, every lane of
// a register one vertex.
#include "diffuse_shade.h"

#include <limits>

#include "shade_lanes.h"

namespace foton::kern {

namespace {

using namespace lanes;

FloatV mis_weight(const DiffuseRules& r, const FloatV& pa, const FloatV& pb) {
    const FloatV zero(0.f), one(1.f);
    switch (r.mis) {
        case DiffuseMis::Balance:
            return pa / (pa + pb);
        case DiffuseMis::Power:  // exponent 2 (the caller keeps others scalar)
            return pa * pa / (pa * pa + pb * pb);
        case DiffuseMis::Maximum:
            return xsimd::select(pa * FloatV(kDiffuseMaxTie) >= pb, one, zero);
        case DiffuseMis::None:
            break;
    }
    return one;
}

void shade_lanes(const Lanes& l, const DiffuseRules& rules) {
    reconstruct_surface(l);
    const FloatV zero(0.f), one(1.f), inv_pi(kDiffuseInvPi);
    const V3 p = l.in3(kDvPx), ng = l.in3(kDvNgx), ns = l.in3(kDvNsx);
    const FloatV eps = l.in(kDvEps);
    const V3 rho = l.in3(kDvRhoR), beta = l.in3(kDvBetaR);
    const V3 f{rho.x * inv_pi, rho.y * inv_pi, rho.z * inv_pi};
    V3 s, t;
    shading_frame(ns, s, t);
    const FloatV wo_z = dot(l.in3(kDvWox), ns);

    // A rectangle light's sample: a point uniform on its area, its solid-angle density.
    const MaskV rect = l.in(kDvLrect) != zero;
    FloatV pl = l.in(kDvLightPdf), dist = l.in(kDvLdist);
    V3 lw = l.in3(kDvLwx), q = l.in3(kDvLpx), nq = l.in3(kDvLnx);
    if (xsimd::any(rect)) {
        const V3 qr = (q + l.in3(kDvLe1x) * l.in(kDvLu0)) + l.in3(kDvLe2x) * l.in(kDvLu1);
        const V3 to = qr - p;
        const FloatV d2 = dot(to, to);
        const FloatV dr = simd::vsqrt(d2);
        const V3 wr = to * (one / dr);
        const FloatV cos_r = neg(dot(nq, wr));
        const FloatV pr = pl * (d2 / (cos_r * l.in(kDvLarea)));
        pl = xsimd::select(rect, xsimd::select((d2 != zero) & (cos_r > zero), pr, zero), pl);
        dist = xsimd::select(rect, dr, dist);
        lw = select(rect, wr, lw);
        nq = select(rect & (dot(nq, wr) >= zero), neg(nq), nq);
        q = select(rect, qr, q);
    }

    // Next event estimation.
    const FloatV cos_l = dot(lw, ns);
    MaskV shadow = (pl > zero) & (dot(lw, ng) > zero) & (wo_z * cos_l > zero);
    const FloatV pb = xsimd::abs(cos_l) * inv_pi;
    const FloatV w = xsimd::select(l.in(kDvLightFull) != zero, one, mis_weight(rules, pl, pb));
    const FloatV k = xsimd::abs(cos_l) * w / pl;
    const V3 li = l.in3(kDvLiR);
    V3 value{beta.x * f.x * li.x * k, beta.y * f.y * li.y * k, beta.z * f.z * li.z * k};
    shadow = shadow & ((value.x != zero) | (value.y != zero) | (value.z != zero));
    value = select(shadow, value, V3{zero, zero, zero});
    l.out(kDvShadowValid, xsimd::select(shadow, one, zero));
    l.out3(kDvSvR, value);
    // Both ends pushed off their surfaces towards each other (surface.h), or towards a light
    // at infinity along the direction.
    const MaskV at_infinity = xsimd::isinf(dist);
    const V3 o = offset(p, ng, eps, select(at_infinity, lw, q - p));
    const FloatV eps_q =
        FloatV(kDiffuseOffset) * (max3(xsimd::abs(q.x), xsimd::abs(q.y), xsimd::abs(q.z)) + dist);
    const FloatV toward = xsimd::select(dot(nq, o - q) >= zero, eps_q, neg(eps_q));
    const V3 d = (q + nq * toward) - o;
    const FloatV len = simd::vsqrt(dot(d, d));
    const V3 dn = select(len > zero, d * (one / len), d);
    l.out3(kDvSox, o);
    l.out3(kDvSdx, select(at_infinity, lw, dn));
    l.out(kDvStmax, xsimd::select(at_infinity, FloatV(std::numeric_limits<float>::infinity()),
                                  len * FloatV(1.f - 1e-4f)));

    // The continuation: a cosine-weighted direction.
    const FloatV da = FloatV(2.f) * l.in(kDvU0)-one, db = FloatV(2.f) * l.in(kDvU1)-one;
    const MaskV centre = (da == zero) & (db == zero);
    const MaskV wide = xsimd::abs(da) > xsimd::abs(db);
    const FloatV quarter_pi(0.25f * kDiffusePi);
    const FloatV r = xsimd::select(wide, da, db);
    const FloatV x = quarter_pi * xsimd::select(wide, db / da, da / db);
    FloatV sx, cx;
    sincos_quarter(x, sx, cx);
    // Beyond pi/4 the angle is pi/2 - x: cosine and sine swap.
    const FloatV lx = xsimd::select(centre, zero, r * xsimd::select(wide, cx, sx));
    const FloatV ly = xsimd::select(centre, zero, r * xsimd::select(wide, sx, cx));
    FloatV lz = simd::vsqrt(simd::vmax(one - lx * lx - ly * ly, zero));
    lz = xsimd::select(wo_z < zero, neg(lz), lz);
    const FloatV cz = xsimd::abs(lz);
    const V3 wi = s * lx + t * ly + ns * lz;
    const FloatV pdf = cz * inv_pi;
    const FloatV kn = cz / pdf;
    V3 nb{beta.x * (f.x * kn), beta.y * (f.y * kn), beta.z * (f.z * kn)};
    MaskV next = (wo_z * lz > zero) & (dot(wi, ng) > zero) &
                 ((nb.x != zero) | (nb.y != zero) | (nb.z != zero));
    if (rules.roulette) {
        const FloatV qr = simd::vmin(max3(nb.x, nb.y, nb.z) * l.in(kDvEtaScale), one);
        next = next & (l.in(kDvURoulette) < qr);
        nb = nb * (one / qr);
    }
    l.out(kDvNextValid, xsimd::select(next, one, zero));
    l.out3(kDvNox, offset(p, ng, eps, wi));
    l.out3(kDvNdx, wi);
    l.out3(kDvNbetaR, nb);
    l.out(kDvNpdf, pdf);
}

}  // namespace

std::size_t diffuse_shade_width() {
    return simd::kWidth;
}

void shade_diffuse(const DiffuseVertices& v, std::size_t n, const DiffuseRules& rules) {
    for (std::size_t i = 0; i < n; i += simd::kWidth) shade_lanes(Lanes{v, i}, rules);
}

}  // namespace foton::kern
