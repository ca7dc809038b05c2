#pragma once
// The BSDF of a diffuse-kernel lane at SIMD width, as shade_diffuse (the path tracer) and
// shade_importance (the light tracer) both evaluate and sample it: a Lambertian or Oren–Nayar
// lobe of reflectance rho, a glossy lobe (glossy_lanes.h), or both, mixed as Bsdf::f,
// Bsdf::pdf and Bsdf::sample mix them. Reflection only: every lobe here keeps wi on wo's side
// of the shading normal. The scalar twin is diffuse_lobes_scalar.h.
#include "glossy_lanes.h"

namespace foton::kern::lanes {

// Oren–Nayar's f / rho for local directions wo, wi on one side (bsdf.cpp's lobe_f, operation
// for operation); B = 0 gives 1 / pi exactly, Lambert's.
inline FloatV oren_nayar(const V3& wo, const V3& wi, const FloatV& a, const FloatV& b) {
    const FloatV zero(0.f), inv_pi(kDiffuseInvPi), tiny(1e-4f), one(1.f);
    const FloatV ci = xsimd::abs(wi.z), co = xsimd::abs(wo.z);
    const FloatV si = simd::vsqrt(simd::vmax(one - ci * ci, zero));
    const FloatV so = simd::vsqrt(simd::vmax(one - co * co, zero));
    const FloatV cos_dphi = xsimd::select(
        (si > tiny) & (so > tiny), simd::vmax((wi.x * wo.x + wi.y * wo.y) / (si * so), zero), zero);
    // alpha = the larger polar angle, beta = the smaller.
    const FloatV sin_alpha = xsimd::select(ci > co, so, si);
    const FloatV tan_beta = xsimd::select(ci > co, si / ci, so / co);
    return xsimd::select(b == zero, inv_pi, inv_pi * (a + b * cos_dphi * sin_alpha * tan_beta));
}

// A lane's lobes seen from wo (local, in the shading frame).
struct DiffuseLobes {
    V3 wo;
    V3 rho, f_lambert;  // f_lambert = rho / pi
    FloatV on_a, on_b;
    bool rough;  // some lane is Oren–Nayar's: its f depends on the directions
    MaskV glossy;
    bool any_glossy;
    GlossyLanes g;
    FloatV wd, wg;  // the lobes' sampling weights (glossy lanes)

    DiffuseLobes(const Lanes& l, const V3& wo_local)
        : wo(wo_local),
          rho(l.in3(kDvRhoR)),
          f_lambert{rho.x * FloatV(kDiffuseInvPi), rho.y * FloatV(kDiffuseInvPi),
                    rho.z * FloatV(kDiffuseInvPi)},
          on_a(l.in(kDvOnA)),
          on_b(l.in(kDvOnB)),
          rough(xsimd::any(on_b != FloatV(0.f))),
          glossy(l.in(kDvGlossKind) != FloatV(0.f)),
          any_glossy(xsimd::any(glossy)),
          g(any_glossy ? GlossyLanes(l) : GlossyLanes()),
          wd(l.in(kDvDiffuseWeight)),
          wg(l.in(kDvGlossWeight)) {}

    // The diffuse lobe's f at wi, on wo's side (no hemisphere test).
    V3 diffuse_f(const V3& wi) const {
        if (!rough) return f_lambert;
        const FloatV k = oren_nayar(wo, wi, on_a, on_b);
        return V3{rho.x * k, rho.y * k, rho.z * k};
    }

    // Glossy lanes: the two lobes' f summed and their densities mixed by the sampling weights
    // at wi (Bsdf::f, Bsdf::pdf), given the diffuse lobe's f there; each lobe's density too.
    FloatV mixed(const V3& wi, const V3& fd, V3& f_sum, FloatV& pdf_d, FloatV& pdf_g) const {
        const FloatV zero(0.f);
        V3 fg;
        glossy_eval(g, wo, wi, fg, pdf_g);
        const MaskV same = wo.z * wi.z > zero;
        const V3 fds = select(same, fd, V3{zero, zero, zero});
        f_sum = fds + fg;
        pdf_d = xsimd::select(same, xsimd::abs(wi.z) * FloatV(kDiffuseInvPi), zero);
        return (wd * pdf_d + wg * pdf_g) / (wd + wg);
    }

    // Bsdf::f and Bsdf::pdf at wi: the diffuse lobe on wo's side, the mixture on glossy lanes.
    void eval(const V3& wi, V3& fv, FloatV& pdf) const {
        const FloatV zero(0.f);
        const MaskV same = wo.z * wi.z > zero;
        const V3 fd = diffuse_f(wi);
        fv = select(same, fd, V3{zero, zero, zero});
        pdf = xsimd::select(same, xsimd::abs(wi.z) * FloatV(kDiffuseInvPi), zero);
        if (any_glossy) {
            V3 fm;
            FloatV pdf_d, pdf_g;
            const FloatV pm = mixed(wi, fd, fm, pdf_d, pdf_g);
            fv = select(glossy, fm, fv);
            pdf = xsimd::select(glossy, pm, pdf);
        }
    }

    // Bsdf::f at wi (eval's f; the unused density is left to the compiler).
    V3 f(const V3& wi) const {
        V3 fv;
        FloatV pdf;
        eval(wi, fv, pdf);
        return fv;
    }
};

// Bsdf::sample's result: the local direction, f and pdf there, and where it is valid.
struct LobeSample {
    V3 wi, f;
    FloatV pdf;
    MaskV ok;
};

// Bsdf::sample from (kDvUChoice, kDvU0, kDvU1): diffuse lanes a cosine-weighted direction
// (Shirley–Chiu disc, Malley) on wo's side; glossy lanes the lobe by kDvUChoice in the BSDF's
// order, its direction, then the mixture's f and pdf there.
inline LobeSample sample_lobes(const DiffuseLobes& b, const Lanes& l) {
    const FloatV zero(0.f), one(1.f), inv_pi(kDiffuseInvPi);
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
    lz = xsimd::select(b.wo.z < zero, neg(lz), lz);
    LobeSample s;
    s.wi = V3{lx, ly, lz};
    s.pdf = xsimd::abs(lz) * inv_pi;
    s.f = b.diffuse_f(s.wi);
    s.ok = b.wo.z * lz > zero;
    if (b.any_glossy) {
        const MaskV glossy_first = l.in(kDvGlossFirst) != zero;
        const FloatV w_first = xsimd::select(glossy_first, b.wg, b.wd);
        const FloatV w_second = xsimd::select(glossy_first, b.wd, b.wg);
        const FloatV target = l.in(kDvUChoice) * (b.wd + b.wg);
        const MaskV first = (w_first > zero) & ((target < w_first) | ~(w_second > zero));
        const MaskV take_glossy = (glossy_first & first) | (~glossy_first & ~first);
        MaskV sampled = b.glossy;
        const V3 wg_local = glossy_sample(b.g, b.wo, l.in(kDvU0), l.in(kDvU1), sampled);
        MaskV ok = select_mask(take_glossy, sampled, b.glossy);
        const V3 wl = select(take_glossy, wg_local, s.wi);
        V3 fm;
        FloatV pdf_d, pdf_g;
        const FloatV pm = b.mixed(wl, b.diffuse_f(wl), fm, pdf_d, pdf_g);
        ok = ok & select_mask(take_glossy, pdf_g > zero, pdf_d > zero) & (pm > zero);
        s.wi = select(b.glossy, wl, s.wi);
        s.f = select(b.glossy, fm, s.f);
        s.pdf = xsimd::select(b.glossy, pm, s.pdf);
        s.ok = select_mask(b.glossy, ok, s.ok);
    }
    return s;
}

}  // namespace foton::kern::lanes
