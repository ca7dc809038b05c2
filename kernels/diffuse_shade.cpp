// shade_diffuse at SIMD width: every branch of the scalar twin becomes a select, every lane of
// a register one vertex.
#include "diffuse_shade.h"

#include <limits>

#include "diffuse_lobes.h"

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

void shade_lanes(const Lanes& l, const DiffuseRules& rules) {
    reconstruct_surface(l);
    const FloatV zero(0.f), one(1.f), inv_pi(kDiffuseInvPi);
    const V3 p = l.in3(kDvPx), ng = l.in3(kDvNgx), ns = l.in3(kDvNsx);
    const FloatV eps = l.in(kDvEps);
    const V3 beta = l.in3(kDvBetaR);
    V3 s, t;
    shading_frame(ns, s, t);
    const V3 wo_world = l.in3(kDvWox);
    const FloatV wo_z = dot(wo_world, ns);
    const DiffuseLobes lobes(l, V3{dot(wo_world, s), dot(wo_world, t), wo_z});

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
    const V3 fl = lobes.diffuse_f(wl);
    V3 value{beta.x * fl.x * li.x * k, beta.y * fl.y * li.y * k, beta.z * fl.z * li.z * k};
    // Lanes with a glossy lobe: f and pdf are the two lobes' (Bsdf::f and Bsdf::pdf: the sum,
    // and the densities mixed by the sampling weights).
    const MaskV glossy = lobes.glossy;
    if (lobes.any_glossy) {
        V3 fm;
        FloatV pdf_d, pdf_g;
        const FloatV pm = lobes.mixed(wl, fl, fm, pdf_d, pdf_g);
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

    // The continuation (Bsdf::sample), throughput f |cos| / pdf.
    const LobeSample smp = sample_lobes(lobes, l);
    const V3 wi = s * smp.wi.x + t * smp.wi.y + ns * smp.wi.z;
    const FloatV pdf = smp.pdf;
    const FloatV kn = xsimd::abs(smp.wi.z) / pdf;
    V3 nb{beta.x * (smp.f.x * kn), beta.y * (smp.f.y * kn), beta.z * (smp.f.z * kn)};
    MaskV next = smp.ok & (dot(wi, ng) > zero);
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
