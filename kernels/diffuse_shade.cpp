// shade_diffuse at SIMD width: every branch of the scalar twin becomes a select, every lane of
// a register one vertex.
#include "diffuse_shade.h"

#include <limits>

#include "diffuse_shade_math.h"
#include "simd.h"

namespace foton::kern {

namespace {

using simd::FloatV;
using simd::MaskV;

// -x by its sign bit, as C++'s unary minus on a float: xsimd's AVX-512 negation is 0 - x,
// which turns +0 into +0, not -0, and a frame built on an axis-aligned normal then flips
// (copysign reads that sign) where the scalar twin's and the engine's does not.
inline FloatV neg(const FloatV& x) {
    return xsimd::bitwise_xor(x, FloatV(-0.f));
}

struct V3 {
    FloatV x, y, z;
};
inline V3 operator+(const V3& a, const V3& b) {
    return {a.x + b.x, a.y + b.y, a.z + b.z};
}
inline V3 operator-(const V3& a, const V3& b) {
    return {a.x - b.x, a.y - b.y, a.z - b.z};
}
inline V3 operator*(const V3& a, const FloatV& s) {
    return {a.x * s, a.y * s, a.z * s};
}
inline FloatV dot(const V3& a, const V3& b) {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}
inline V3 select(const MaskV& m, const V3& a, const V3& b) {
    return {xsimd::select(m, a.x, b.x), xsimd::select(m, a.y, b.y), xsimd::select(m, a.z, b.z)};
}
inline FloatV max3(const FloatV& a, const FloatV& b, const FloatV& c) {
    return simd::vmax(simd::vmax(a, b), c);
}

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

inline V3 offset(const V3& p, const V3& ng, const FloatV& eps, const V3& w) {
    return select(dot(w, ng) >= FloatV(0.f), p + ng * eps, p - ng * eps);
}

struct Lanes {
    const DiffuseVertices& v;
    std::size_t i;
    FloatV in(uint32_t c) const { return FloatV::load_unaligned(v.col(c) + i); }
    V3 in3(uint32_t c) const { return {in(c), in(c + 1), in(c + 2)}; }
    void out(uint32_t c, const FloatV& a) const { a.store_unaligned(v.col(c) + i); }
    void out3(uint32_t c, const V3& a) const {
        out(c, a.x);
        out(c + 1, a.y);
        out(c + 2, a.z);
    }
};

inline V3 cross(const V3& a, const V3& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline V3 neg(const V3& a) {
    return {neg(a.x), neg(a.y), neg(a.z)};
}

// The surface of the lanes whose kDvSurface is not 0, written into the surface columns.
void reconstruct_surface(const Lanes& l) {
    const FloatV zero(0.f), one(1.f);
    const FloatV kind = l.in(kDvSurface);
    const MaskV made = kind != zero;
    if (!xsimd::any(made)) return;
    const FloatV t = l.in(kDvT), u = l.in(kDvU), v = l.in(kDvV);
    const V3 dir = neg(l.in3(kDvWox));
    const V3 a0 = l.in3(kDvA0x), a1 = l.in3(kDvA1x), a2 = l.in3(kDvA2x);
    // A triangle: the barycentric point, the normal of its corners' cross product, and for a
    // smooth one the normalised interpolated vertex normal.
    const FloatV w = (one - u) - v;
    const V3 p_tri = (a0 * w + a1 * u) + a2 * v;
    const V3 c = cross(a1 - a0, a2 - a0);
    const V3 ng_tri = c * (one / simd::vsqrt(dot(c, c)));
    const V3 n_smooth = (l.in3(kDvN0x) * w + l.in3(kDvN1x) * u) + l.in3(kDvN2x) * v;
    const FloatV len = simd::vsqrt(dot(n_smooth, n_smooth));
    const V3 ns_tri = select((kind == FloatV(2.f)) & (len > zero), n_smooth * (one / len), ng_tri);
    // A sphere: o + t d, the radius' direction.
    const MaskV sphere = kind == FloatV(3.f);
    const V3 p_sph = l.in3(kDvOx) + dir * t;
    const V3 n_sph = (p_sph - a0) * (one / a1.x);
    const V3 p = select(sphere, p_sph, p_tri);
    V3 ng = select(sphere, n_sph, ng_tri), ns = select(sphere, n_sph, ns_tri);
    // Both normals towards the side the ray came from; a shading normal that leans past the
    // true surface gives way to the geometric one.
    const MaskV back = dot(ng, dir) >= zero;
    ng = select(back, neg(ng), ng);
    ns = select(back, neg(ns), ns);
    ns = select(dot(ns, dir) >= zero, ng, ns);
    const FloatV eps =
        FloatV(kDiffuseOffset) * (max3(xsimd::abs(p.x), xsimd::abs(p.y), xsimd::abs(p.z)) + t);
    l.out3(kDvPx, select(made, p, l.in3(kDvPx)));
    l.out3(kDvNgx, select(made, ng, l.in3(kDvNgx)));
    l.out3(kDvNsx, select(made, ns, l.in3(kDvNsx)));
    l.out(kDvEps, xsimd::select(made, eps, l.in(kDvEps)));
}

void shade_lanes(const Lanes& l, const DiffuseRules& rules) {
    reconstruct_surface(l);
    const FloatV zero(0.f), one(1.f), inv_pi(kDiffuseInvPi);
    const V3 p = l.in3(kDvPx), ng = l.in3(kDvNgx), ns = l.in3(kDvNsx);
    const FloatV eps = l.in(kDvEps);
    const V3 rho = l.in3(kDvRhoR), beta = l.in3(kDvBetaR);
    const V3 f{rho.x * inv_pi, rho.y * inv_pi, rho.z * inv_pi};
    // The frame around the shading normal (Duff et al. 2017).
    const FloatV sign = xsimd::copysign(one, ns.z);
    const FloatV a = FloatV(-1.f) / (sign + ns.z);
    const FloatV b = ns.x * ns.y * a;
    const V3 s{one + sign * ns.x * ns.x * a, sign * b, neg(sign) * ns.x};
    const V3 t{b, sign + ns.y * ns.y * a, neg(ns.y)};
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
