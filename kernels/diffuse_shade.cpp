// shade_diffuse at SIMD width: every branch of the scalar twin becomes a select, every lane of
// a register one vertex.
#include "diffuse_shade.h"

#include <limits>

#include "glossy_lanes.h"

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
        case DiffuseMis::Mean:
            return xsimd::select(pb > zero, FloatV(0.5f), one);
        case DiffuseMis::None:
            break;
    }
    return one;
}

// Oren–Nayar's f / rho for local directions wo, wi on one side (bsdf.cpp's lobe_f, operation
// for operation); B = 0 gives 1 / pi exactly, Lambert's.
FloatV oren_nayar(const V3& wo, const V3& wi, const FloatV& a, const FloatV& b) {
    const FloatV zero(0.f), one(1.f), inv_pi(kDiffuseInvPi), tiny(1e-4f);
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

void shade_lanes(const Lanes& l, const DiffuseRules& rules) {
    reconstruct_surface(l);
    const FloatV zero(0.f), one(1.f), inv_pi(kDiffuseInvPi);
    const V3 p = l.in3(kDvPx), ng = l.in3(kDvNgx), ns = l.in3(kDvNsx);
    const FloatV eps = l.in(kDvEps);
    const V3 rho = l.in3(kDvRhoR), beta = l.in3(kDvBetaR);
    const V3 f{rho.x * inv_pi, rho.y * inv_pi, rho.z * inv_pi};
    V3 s, t;
    shading_frame(ns, s, t);
    const V3 wo_world = l.in3(kDvWox);
    const FloatV wo_z = dot(wo_world, ns);
    // Oren–Nayar lanes: f depends on the directions (else f = rho / pi).
    const FloatV on_a = l.in(kDvOnA), on_b = l.in(kDvOnB);
    const bool rough = xsimd::any(on_b != zero);
    const V3 wo{dot(wo_world, s), dot(wo_world, t), wo_z};
    auto f_at = [&](const V3& wi) {
        if (!rough) return f;
        const FloatV k = oren_nayar(wo, wi, on_a, on_b);
        return V3{rho.x * k, rho.y * k, rho.z * k};
    };

    // A rectangle's or a triangle's sample: a point uniform on its area (a triangle's by the
    // low-distortion square-to-triangle map of warp::uniform_triangle), its solid-angle
    // density.
    const FloatV kind = l.in(kDvLkind);
    const MaskV rect = (kind == FloatV(kLightParallelogram)) | (kind == FloatV(kLightTriangle));
    FloatV pl = l.in(kDvLightPdf), dist = l.in(kDvLdist);
    V3 lw = l.in3(kDvLwx), q = l.in3(kDvLpx), nq = l.in3(kDvLnx);
    if (xsimd::any(rect)) {
        FloatV a = l.in(kDvLu0), b = l.in(kDvLu1);
        const MaskV tri = kind == FloatV(kLightTriangle);
        const V3 c1 = l.in3(kDvLe1x), c2 = l.in3(kDvLe2x);
        V3 qr = (q + c1 * a) + c2 * b;
        if (xsimd::any(tri)) {
            const MaskV below = a < b;
            const FloatV half_a = FloatV(0.5f) * a, half_b = FloatV(0.5f) * b;
            const FloatV b0 = xsimd::select(below, half_a, a - half_b);
            const FloatV b1 = xsimd::select(below, b - half_a, half_b);
            // warp::uniform_triangle's barycentrics of the second and third corner, and the
            // corners weighted as LightSet::sample_li weighs them (c1, c2 are corners here).
            const FloatV bx = b1, by = (one - b0) - b1;
            const V3 qt = (q * ((one - bx) - by) + c1 * bx) + c2 * by;
            qr = select(tri, qt, qr);
        }
        const V3 to = qr - p;
        const FloatV d2 = dot(to, to);
        const FloatV dr = simd::vsqrt(d2);
        const V3 wr = to * (one / dr);
        FloatV cos_r = neg(dot(nq, wr));
        cos_r = xsimd::select(l.in(kDvLtwoSided) != zero, xsimd::abs(cos_r), cos_r);
        const FloatV pr = pl * (d2 / (cos_r * l.in(kDvLarea)));
        pl = xsimd::select(rect, xsimd::select((d2 != zero) & (cos_r > zero), pr, zero), pl);
        dist = xsimd::select(rect, dr, dist);
        lw = select(rect, wr, lw);
        nq = select(rect & (dot(nq, wr) >= zero), neg(nq), nq);
        q = select(rect, qr, q);
    }

    // An emitting sphere's sample: uniform in the cone it subtends, the point placed on it by
    // its angle at the centre (LightSet::sample_li's arithmetic); from inside a one-sided
    // sphere nothing (its inside does not emit).
    const MaskV sphere = kind == FloatV(kLightSphere);
    if (xsimd::any(sphere)) {
        const V3 c = l.in3(kDvLpx);
        const FloatV r = l.in(kDvLe1x);
        const V3 to_c = c - p;
        const FloatV dc2 = dot(to_c, to_c);
        const FloatV r2 = r * r;
        const MaskV outside = dc2 > r2 * FloatV(1.0001f);
        const V3 wc = to_c * (one / simd::vsqrt(dc2));
        const FloatV sin2_max = r2 / dc2;
        const FloatV omc = sin2_max / (one + simd::vsqrt(simd::vmax(one - sin2_max, zero)));
        const FloatV v = l.in(kDvLu0)*omc;
        const FloatV cos_t = one - v, sin2_t = v * (FloatV(2.f) - v);
        const FloatV cos_a = sin2_t / simd::vsqrt(sin2_max) +
                             cos_t * simd::vsqrt(simd::vmax(one - sin2_t / sin2_max, zero));
        const FloatV sin_a = simd::vsqrt(simd::vmax(one - cos_a * cos_a, zero));
        FloatV sin_p, cos_p;
        sincos_turn(l.in(kDvLu1), sin_p, cos_p);
        V3 fs, ft;
        shading_frame(wc, fs, ft);
        const FloatV lx = sin_a * cos_p, ly = sin_a * sin_p, lz = neg(cos_a);
        const V3 n = V3{(fs.x * lx + ft.x * ly) + wc.x * lz, (fs.y * lx + ft.y * ly) + wc.y * lz,
                        (fs.z * lx + ft.z * ly) + wc.z * lz};
        const V3 qs = c + n * r;
        const V3 to = qs - p;
        const FloatV ds = simd::vsqrt(dot(to, to));
        const FloatV pdf = one / (FloatV(2.f * kDiffusePi) * omc);
        const MaskV ok = outside & (pdf > zero) & (ds > zero);
        pl = xsimd::select(sphere, xsimd::select(ok, pl * pdf, zero), pl);
        dist = xsimd::select(sphere, ds, dist);
        lw = select(sphere, to * (one / ds), lw);
        nq = select(sphere, n, nq);
        q = select(sphere, qs, q);
    }

    // Next event estimation.
    const FloatV cos_l = dot(lw, ns);
    MaskV shadow = (pl > zero) & (dot(lw, ng) > zero) & (wo_z * cos_l > zero);
    const FloatV pb = xsimd::abs(cos_l) * inv_pi;
    const MaskV full = l.in(kDvLightFull) != zero;
    const FloatV w = xsimd::select(full, one, mis_weight(rules, pl, pb));
    const FloatV k = xsimd::abs(cos_l) * w / pl;
    const V3 li = l.in3(kDvLiR);
    const V3 wl{dot(lw, s), dot(lw, t), cos_l};
    const V3 fl = f_at(wl);
    V3 value{beta.x * fl.x * li.x * k, beta.y * fl.y * li.y * k, beta.z * fl.z * li.z * k};
    // Lanes with a glossy lobe: f and pdf are the two lobes' (Bsdf::f and Bsdf::pdf: the sum,
    // and the densities mixed by the sampling weights).
    const MaskV glossy = l.in(kDvGlossKind) != zero;
    const bool any_glossy = xsimd::any(glossy);
    const GlossyLanes g = any_glossy ? GlossyLanes(l) : GlossyLanes();
    const FloatV wd = l.in(kDvDiffuseWeight), wg = l.in(kDvGlossWeight);
    auto mixed = [&](const V3& wi, const V3& fd, V3& f_sum, FloatV& pdf_d, FloatV& pdf_g) {
        V3 fg;
        glossy_eval(g, wo, wi, fg, pdf_g);
        const MaskV same = wo_z * wi.z > zero;
        const V3 fds = select(same, fd, V3{zero, zero, zero});
        f_sum = fds + fg;
        pdf_d = xsimd::select(same, xsimd::abs(wi.z) * inv_pi, zero);
        return (wd * pdf_d + wg * pdf_g) / (wd + wg);
    };
    if (any_glossy) {
        V3 fm;
        FloatV pdf_d, pdf_g;
        const FloatV pm = mixed(wl, fl, fm, pdf_d, pdf_g);
        const FloatV km =
            xsimd::abs(cos_l) * xsimd::select(full, one, mis_weight(rules, pl, pm)) / pl;
        const V3 vm{beta.x * fm.x * li.x * km, beta.y * fm.y * li.y * km,
                    beta.z * fm.z * li.z * km};
        value = select(glossy, vm, value);
        shadow = select_mask(glossy, (pl > zero) & (dot(lw, ng) > zero), shadow);
    }
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
    V3 wi = s * lx + t * ly + ns * lz;
    FloatV pdf = cz * inv_pi;
    const FloatV kn = cz / pdf;
    const V3 fn = f_at(V3{lx, ly, lz});
    V3 nb{beta.x * (fn.x * kn), beta.y * (fn.y * kn), beta.z * (fn.z * kn)};
    MaskV next = (wo_z * lz > zero) & (dot(wi, ng) > zero);
    if (any_glossy) {
        // Bsdf::sample: the lobe by kDvUChoice in the BSDF's order, its direction, then the
        // mixture's f and pdf there.
        const MaskV glossy_first = l.in(kDvGlossFirst) != zero;
        const FloatV w_first = xsimd::select(glossy_first, wg, wd);
        const FloatV w_second = xsimd::select(glossy_first, wd, wg);
        const FloatV target = l.in(kDvUChoice) * (wd + wg);
        const MaskV first = (w_first > zero) & ((target < w_first) | ~(w_second > zero));
        const MaskV take_glossy = (glossy_first & first) | (~glossy_first & ~first);
        MaskV sampled = glossy;
        const V3 wg_local = glossy_sample(g, wo, l.in(kDvU0), l.in(kDvU1), sampled);
        MaskV ok = select_mask(take_glossy, sampled, glossy);
        const V3 wl_next = select(take_glossy, wg_local, V3{lx, ly, lz});
        V3 fm;
        FloatV pdf_d, pdf_g;
        const FloatV pm = mixed(wl_next, f_at(wl_next), fm, pdf_d, pdf_g);
        ok = ok & select_mask(take_glossy, pdf_g > zero, pdf_d > zero) & (pm > zero);
        const V3 wm = s * wl_next.x + t * wl_next.y + ns * wl_next.z;
        const FloatV cm = xsimd::abs(wl_next.z);
        const FloatV km = cm / pm;
        const V3 nm{beta.x * (fm.x * km), beta.y * (fm.y * km), beta.z * (fm.z * km)};
        ok = ok & (dot(wm, ng) > zero);
        wi = select(glossy, wm, wi);
        nb = select(glossy, nm, nb);
        pdf = xsimd::select(glossy, pm, pdf);
        next = select_mask(glossy, ok, next);
    }
    next = next & ((nb.x != zero) | (nb.y != zero) | (nb.z != zero));
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

std::size_t shade_width() {
    return simd::kWidth;
}

void shade_diffuse(const ShadeTable& v, std::size_t n, const DiffuseRules& rules) {
    for (std::size_t i = 0; i < n; i += simd::kWidth) shade_lanes(Lanes{v, i}, rules);
}

}  // namespace foton::kern
