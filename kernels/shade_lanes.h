#pragma once
// What the SIMD shading kernels share (diffuse_shade.cpp, specular_shade.cpp): vectors of W
// lanes, a table's lanes as registers, the surface reconstructed from the hit, the shading
// frame. The scalar twins' counterpart is shade_scalar.h; the two do the same IEEE
// operations in the same order.
#include <cstddef>
#include <cstdint>

#include "diffuse_shade.h"
#include "diffuse_shade_math.h"
#include "glossy_math.h"
#include "simd.h"

namespace foton::kern::lanes {

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
// A mask's lanes from a where m holds, from b elsewhere.
inline MaskV select_mask(const MaskV& m, const MaskV& a, const MaskV& b) {
    return (m & a) | (~m & b);
}
inline FloatV max3(const FloatV& a, const FloatV& b, const FloatV& c) {
    return simd::vmax(simd::vmax(a, b), c);
}

inline V3 offset(const V3& p, const V3& ng, const FloatV& eps, const V3& w) {
    return select(dot(w, ng) >= FloatV(0.f), p + ng * eps, p - ng * eps);
}

struct Lanes {
    const ShadeTable& v;
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

// The surface of the lanes whose kDvSurface is not 0, written into the surface columns (and
// kDvFront: 1 where the ray hit the side the geometry's normal points to).
inline void reconstruct_surface(const Lanes& l) {
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
    l.out(kDvFront, xsimd::select(made, xsimd::select(back, zero, one), l.in(kDvFront)));
}

// The frame (s, t, ns) around a unit shading normal (Duff et al. 2017).
inline void shading_frame(const V3& ns, V3& s, V3& t) {
    const FloatV one(1.f);
    const FloatV sign = xsimd::copysign(one, ns.z);
    const FloatV a = FloatV(-1.f) / (sign + ns.z);
    const FloatV b = ns.x * ns.y * a;
    s = V3{one + sign * ns.x * ns.x * a, sign * b, neg(sign) * ns.x};
    t = V3{b, sign + ns.y * ns.y * a, neg(ns.y)};
}

// std::clamp(x, 0, 1): x < 0 ? 0 : (1 < x ? 1 : x).
inline FloatV clamp01(const FloatV& x) {
    const FloatV zero(0.f), one(1.f);
    return xsimd::select(x < zero, zero, xsimd::select(one < x, one, x));
}
// std::max(0.f, x): 0 < x ? x : 0.
inline FloatV pos(const FloatV& x) {
    return simd::vmax(x, FloatV(0.f));
}

inline FloatV fresnel_dielectric(FloatV cos_i, const FloatV& eta_i, const FloatV& eta_t) {
    const FloatV one(1.f);
    cos_i = clamp01(cos_i);
    const FloatV sin_i = simd::vsqrt(pos(one - cos_i * cos_i));
    const FloatV sin_t = eta_i / eta_t * sin_i;
    const FloatV cos_t = simd::vsqrt(pos(one - sin_t * sin_t));
    const FloatV r_par = (eta_t * cos_i - eta_i * cos_t) / (eta_t * cos_i + eta_i * cos_t);
    const FloatV r_perp = (eta_i * cos_i - eta_t * cos_t) / (eta_i * cos_i + eta_t * cos_t);
    return xsimd::select(sin_t >= one, one, FloatV(0.5f) * (r_par * r_par + r_perp * r_perp));
}

inline FloatV fresnel_conductor(FloatV cos_i, const FloatV& eta, const FloatV& k) {
    const FloatV one(1.f), half(0.5f), two(2.f);
    cos_i = clamp01(cos_i);
    const FloatV cos2 = cos_i * cos_i, sin2 = one - cos2;
    const FloatV eta2 = eta * eta, k2 = k * k;
    const FloatV t0 = eta2 - k2 - sin2;
    const FloatV a2b2 = simd::vsqrt(pos(t0 * t0 + FloatV(4.f) * eta2 * k2));
    const FloatV a = simd::vsqrt(pos(half * (a2b2 + t0)));
    const FloatV t1 = a2b2 + cos2, t2 = two * cos_i * a;
    const FloatV rs = (t1 - t2) / (t1 + t2);
    const FloatV t3 = cos2 * a2b2 + sin2 * sin2, t4 = t2 * sin2;
    const FloatV rp = rs * (t3 - t4) / (t3 + t4);
    return half * (rs + rp);
}

// sincos_turn (diffuse_shade_math.h) for W lanes: the same comparisons, polynomial and
// quadrant rotation.
inline void sincos_turn(const FloatV& u, FloatV& s, FloatV& c) {
    const FloatV zero(0.f), one(1.f);
    const FloatV x4 = u * FloatV(4.f);
    auto step = [&](float edge) { return xsimd::select(x4 >= FloatV(edge), one, zero); };
    const FloatV k = ((step(0.5f) + step(1.5f)) + step(2.5f)) + step(3.5f);
    FloatV sr, cr;
    sincos_quarter((x4 - k) * FloatV(1.57079632679489661923f), sr, cr);
    const MaskV q1 = k == one, q2 = k == FloatV(2.f), q3 = k == FloatV(3.f);
    s = xsimd::select(q1, cr, xsimd::select(q2, neg(sr), xsimd::select(q3, neg(cr), sr)));
    c = xsimd::select(q1, neg(sr), xsimd::select(q2, neg(cr), xsimd::select(q3, sr, cr)));
}

// glossy_math.h's log2_poly, exp2_poly, pow_poly, exp_poly and log_poly for W lanes: the same
// polynomials, the same exact splits and joins by bitwise casts.
using IntV = xsimd::batch<int32_t, simd::Arch>;

inline FloatV log2_poly(FloatV x) {
    const FloatV tiny(0x1p-126f), one(1.f);
    x = xsimd::select(x < tiny, tiny, x);
    const IntV bits = xsimd::bitwise_cast<IntV>(x);
    FloatV e = simd::to_float(bits & IntV(0x7f800000)) * FloatV(0x1p-23f) - FloatV(126.f);
    const FloatV m = xsimd::bitwise_cast<FloatV>((bits & IntV(0x007fffff)) | IntV(0x3f000000));
    const MaskV low = m < FloatV(kSqrtHalf);
    e = xsimd::select(low, e - one, e);
    const FloatV r = xsimd::select(low, (m + m) - one, m - one);
    return log2_reduced(r, e);
}

inline FloatV exp2_poly(FloatV x) {
    const MaskV in_range = x >= FloatV(kExp2Min);
    x = xsimd::select(x > FloatV(kExp2Max), FloatV(kExp2Max), x);
    const FloatV n = simd::vfloor(x + FloatV(0.5f));
    const FloatV p = exp2_reduced(x - n);
    const FloatV scale =
        xsimd::bitwise_cast<FloatV>(simd::to_int((n + FloatV(127.f)) * FloatV(0x1p23f)));
    return xsimd::select(in_range, p * scale, FloatV(0.f));
}

inline FloatV pow_poly(const FloatV& x, const FloatV& y) {
    return xsimd::select(x > FloatV(0.f), exp2_poly(y * log2_poly(x)), FloatV(0.f));
}

inline FloatV exp_poly(const FloatV& x) {
    return exp2_poly(x * FloatV(kLog2e));
}

inline FloatV log_poly(const FloatV& x) {
    return log2_poly(x) * FloatV(kLn2);
}

}  // namespace foton::kern::lanes
