#pragma once
// The glossy lobe of shade_diffuse at SIMD width (the modified Phong lobe and the microfacet
// lobes of engine/scene/bsdf.cpp and microfacet.cpp, operation for operation, with powers,
// exponentials and logarithms by glossy_math.h's polynomials): its f and pdf at a pair of
// local directions and a sampled direction. The scalar twin is glossy_scalar.h.
#include <limits>

#include "shade_lanes.h"

namespace foton::kern::lanes {

// A lane's glossy lobe as the table holds it (shade_table.h, kDvGlossKind..).
struct GlossyLanes {
    FloatV kind, nu, nv;
    V3 color;
    FloatV fresnel, ior;
    V3 eta, k;
    MaskV phong, beckmann, cos_power, ggx;
    bool any_phong = false, any_microfacet = false, any_anisotropic = false, any_ggx = false;

    GlossyLanes() = default;
    explicit GlossyLanes(const Lanes& l)
        : kind(l.in(kDvGlossKind)),
          nu(l.in(kDvGlossNu)),
          nv(l.in(kDvGlossNv)),
          color(l.in3(kDvGlossR)),
          fresnel(l.in(kDvFresnel)),
          ior(l.in(kDvIor)),
          eta(l.in3(kDvEtaR)),
          k(l.in3(kDvKR)),
          phong(kind == FloatV(kGlossPhong)),
          beckmann(kind == FloatV(kGlossBeckmann)),
          cos_power(kind == FloatV(kGlossCosPower)),
          ggx(kind == FloatV(kGlossGgx)),
          any_phong(xsimd::any(phong)),
          any_microfacet(xsimd::any(beckmann | cos_power | ggx)),
          any_anisotropic(xsimd::any(cos_power & (nu != nv))),
          any_ggx(xsimd::any(ggx)) {}
    MaskV microfacet() const { return beckmann | cos_power | ggx; }
};

// Fresnel::eval: 1, a dielectric's (from outside, index ior) or a conductor's per channel.
inline V3 glossy_fresnel(const GlossyLanes& g, const FloatV& c) {
    const FloatV one(1.f), two(2.f);
    V3 fr{one, one, one};
    if (xsimd::any(g.fresnel == two)) {
        const FloatV fd = fresnel_dielectric(c, one, g.ior);
        fr = select(g.fresnel == two, V3{fd, fd, fd}, fr);
    }
    if (xsimd::any(g.fresnel == one)) {
        const V3 fc{fresnel_conductor(c, g.eta.x, g.k.x), fresnel_conductor(c, g.eta.y, g.k.y),
                    fresnel_conductor(c, g.eta.z, g.k.z)};
        fr = select(g.fresnel == one, fc, fr);
    }
    return fr;
}

// MicrofacetDistribution::D.
inline FloatV glossy_d(const GlossyLanes& g, const V3& h) {
    const FloatV zero(0.f), one(1.f), c = h.z;
    FloatV d = zero;
    if (xsimd::any(g.beckmann)) {
        const FloatV c2 = c * c;
        const FloatV tan2 = (one - c2) / c2;
        const FloatV a = g.nu;
        const FloatV db =
            exp_poly(neg(tan2) / (a * a)) / ((((FloatV(kDiffusePi) * a) * a) * c2) * c2);
        d = xsimd::select(g.beckmann, db, d);
    }
    if (xsimd::any(g.cos_power)) {
        const FloatV s2 = h.x * h.x + h.y * h.y;
        const FloatV e = xsimd::select(s2 > zero, (g.nu * h.x * h.x + g.nv * h.y * h.y) / s2, g.nu);
        const FloatV dc = simd::vsqrt((g.nu + FloatV(2.f)) * (g.nv + FloatV(2.f))) *
                          FloatV(0.5f * kDiffuseInvPi) * pow_poly(c, e);
        d = xsimd::select(g.cos_power, dc, d);
    }
    if (g.any_ggx) {
        const FloatV x = h.x / g.nu, y = h.y / g.nv;
        const FloatV s = c * c + x * x + y * y;
        const FloatV dg = one / ((((FloatV(kDiffusePi) * g.nu) * g.nv) * s) * s);
        d = xsimd::select(g.ggx, dg, d);
    }
    return xsimd::select(c > zero, d, zero);
}

// Trowbridge–Reitz's Smith Lambda (microfacet.cpp): infinite at the horizon.
inline FloatV ggx_lambda(const GlossyLanes& g, const V3& w) {
    const FloatV one(1.f), z2 = w.z * w.z;
    const FloatV ax = w.x * g.nu, ay = w.y * g.nv;
    const FloatV a2t2 = (ax * ax + ay * ay) / z2;
    return xsimd::select(z2 == FloatV(0.f), FloatV(std::numeric_limits<float>::infinity()),
                         FloatV(0.5f) * (simd::vsqrt(one + a2t2) - one));
}

// lobe_f and lobe_pdf of the glossy lobe at local wo, wi (0 where it has none).
inline void glossy_eval(const GlossyLanes& g, const V3& wo, const V3& wi, V3& f, FloatV& pdf) {
    const FloatV zero(0.f), one(1.f), half_inv_pi(0.5f * kDiffuseInvPi);
    const MaskV up = (wo.z > zero) & (wi.z > zero);
    f = V3{zero, zero, zero};
    pdf = zero;
    if (g.any_phong) {
        const FloatV c = (neg(wo.x) * wi.x + neg(wo.y) * wi.y) + wo.z * wi.z;
        const FloatV pw = pow_poly(c, g.nu);
        const FloatV kf = ((g.nu + FloatV(2.f)) * FloatV(0.5f)) * FloatV(kDiffuseInvPi) * pw;
        const FloatV kp = ((g.nu + one) * FloatV(0.5f)) * FloatV(kDiffuseInvPi) * pw;
        const MaskV on = g.phong & up & (c > zero);
        f = select(on, g.color * kf, f);
        pdf = xsimd::select(on, kp, pdf);
    }
    if (g.any_microfacet) {
        const V3 hv = wo + wi;
        const V3 h = hv * (one / simd::vsqrt(dot(hv, hv)));
        const FloatV oh_signed = dot(wo, h);
        const FloatV oh = xsimd::abs(oh_signed);
        const FloatV kg = FloatV(2.f) * xsimd::abs(h.z) / oh;
        // std::min's operand order (a NaN falls the same way as in the twin).
        const FloatV gv = xsimd::select(
            oh == zero, zero,
            simd::vmin(kg * xsimd::abs(wi.z), simd::vmin(kg * xsimd::abs(wo.z), one)));
        const V3 fr = glossy_fresnel(g, dot(wi, h));
        const FloatV d = glossy_d(g, h);
        FloatV shadowing = gv;
        FloatV pm = (d * xsimd::abs(h.z)) / (FloatV(4.f) * oh_signed);
        if (g.any_ggx) {
            // Smith's height-correlated G, and the visible normals' pdf G1(wo) D / (4 wo.z).
            const FloatV lo = ggx_lambda(g, wo), li = ggx_lambda(g, wi);
            shadowing = xsimd::select(g.ggx, one / ((one + lo) + li), shadowing);
            pm = xsimd::select(g.ggx, ((one / (one + lo)) * d) / (FloatV(4.f) * wo.z), pm);
        }
        const FloatV kf = d * shadowing / ((FloatV(4.f) * wo.z) * wi.z);
        const V3 fm{(g.color.x * fr.x) * kf, (g.color.y * fr.y) * kf, (g.color.z * fr.z) * kf};
        const MaskV on = g.microfacet() & up;
        f = select(on, fm, f);
        pdf = xsimd::select(on, pm, pdf);
    }
}

// MicrofacetDistribution::sample_visible for W lanes (Heitz 2018), the azimuth's sine and
// cosine given.
inline V3 ggx_visible_normal(const GlossyLanes& g, const V3& wo, const FloatV& u0,
                             const FloatV& sin_p, const FloatV& cos_p) {
    const FloatV zero(0.f), one(1.f);
    const V3 ws{g.nu * wo.x, g.nv * wo.y, wo.z};
    const V3 wh = ws * (one / simd::vsqrt(dot(ws, ws)));
    const FloatV l2 = wh.x * wh.x + wh.y * wh.y;
    const FloatV il = one / simd::vsqrt(l2);
    const MaskV tilted = l2 > zero;
    const V3 t1{xsimd::select(tilted, neg(wh.y) * il, one), xsimd::select(tilted, wh.x * il, zero),
                zero};
    const V3 t2 = cross(wh, t1);
    const FloatV r = simd::vsqrt(u0);
    const FloatV p1 = r * cos_p;
    const FloatV s = FloatV(0.5f) * (one + wh.z);
    const FloatV p2 = (one - s) * simd::vsqrt(simd::vmax(one - p1 * p1, zero)) + s * (r * sin_p);
    const FloatV pz = simd::vsqrt(simd::vmax((one - p1 * p1) - p2 * p2, zero));
    const V3 nh = (t1 * p1 + t2 * p2) + wh * pz;
    const V3 hs{g.nu * nh.x, g.nv * nh.y, simd::vmax(FloatV(1e-6f), nh.z)};
    return hs * (one / simd::vsqrt(dot(hs, hs)));
}

// lobe_sample's direction for the glossy lobe from u (local; `ok` false where it gives none):
// Phong's cos^n cone around the mirror direction, or the microfacet normal sampled by
// D cos and wo mirrored about it. An Ashikhmin–Shirley azimuth comes from the quarter-turn
// inversion of microfacet.cpp; its cosine and sine are those of atan(r tan x) written as the
// normalised (cos x, r sin x), the same angle without the inverse tangent.
inline V3 glossy_sample(const GlossyLanes& g, const V3& wo, const FloatV& u0, const FloatV& u1,
                        MaskV& ok) {
    const FloatV zero(0.f), one(1.f), two(2.f);
    FloatV sin_p, cos_p;
    sincos_turn(u1, sin_p, cos_p);
    V3 wi{zero, zero, one};
    if (g.any_phong) {
        const V3 m{neg(wo.x), neg(wo.y), wo.z};
        const FloatV ca = pow_poly(u0, one / (g.nu + one));
        const FloatV sa = simd::vsqrt(simd::vmax(one - ca * ca, zero));
        V3 fs, ft;
        shading_frame(m, fs, ft);
        const V3 wp = (fs * (sa * cos_p) + ft * (sa * sin_p)) + m * ca;
        wi = select(g.phong, wp, wi);
    }
    if (g.any_microfacet) {
        FloatV cp = cos_p, sp = sin_p, cos_t = one;
        if (xsimd::any(g.beckmann)) {
            const FloatV tan2 = (neg(g.nu) * g.nu) * log_poly(one - u0);
            cos_t = xsimd::select(g.beckmann, one / simd::vsqrt(one + tan2), cos_t);
        }
        if (xsimd::any(g.cos_power)) {
            if (g.any_anisotropic) {
                const FloatV q = FloatV(4.f) * u1;
                auto step = [&](float edge) { return xsimd::select(q >= FloatV(edge), one, zero); };
                const FloatV quadrant = (step(1.f) + step(2.f)) + step(3.f);
                const FloatV f = q - quadrant;
                FloatV sx, cx;
                sincos_turn(f * FloatV(0.25f), sx, cx);
                const FloatV r = simd::vsqrt((g.nu + two) / (g.nv + two));
                const FloatV rs = r * sx;
                const FloatV inv = one / simd::vsqrt(cx * cx + rs * rs);
                const FloatV cb = cx * inv, sb = rs * inv;
                // pi - base, pi + base, 2 pi - base in quadrants 1, 2, 3.
                const MaskV q1 = quadrant == one, q2 = quadrant == two,
                            q3 = quadrant == FloatV(3.f);
                const FloatV ca = xsimd::select(q1 | q2, neg(cb), cb);
                const FloatV sa = xsimd::select(q2 | q3, neg(sb), sb);
                const MaskV aniso = g.cos_power & (g.nu != g.nv);
                cp = xsimd::select(aniso, ca, cp);
                sp = xsimd::select(aniso, sa, sp);
            }
            const FloatV e = g.nu * cp * cp + g.nv * sp * sp;
            cos_t = xsimd::select(g.cos_power, pow_poly(u0, one / (e + two)), cos_t);
        }
        const FloatV sin_t = simd::vsqrt(simd::vmax(one - cos_t * cos_t, zero));
        V3 h{sin_t * cp, sin_t * sp, cos_t};
        if (g.any_ggx) h = select(g.ggx, ggx_visible_normal(g, wo, u0, sin_p, cos_p), h);
        const FloatV oh = dot(wo, h);
        const V3 wm = h * (two * oh) - wo;
        const MaskV micro = g.microfacet();
        wi = select(micro, wm, wi);
        ok = ok & (~micro | (oh > zero));
    }
    ok = ok & (wo.z > zero) & (wi.z > zero);
    return wi;
}

}  // namespace foton::kern::lanes
