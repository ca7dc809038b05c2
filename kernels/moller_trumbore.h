#pragma once
// Möller–Trumbore ray/triangle intersection in three shapes:
//   * intersect_triangle_scalar: the scalar reference twin, one ray against one triangle;
//   * intersect_block / occluded_block: one ray against a TriangleBlock of W triangles;
//   * intersect_packet: a packet of W rays (SoA) against one triangle.
// All three evaluate the same expressions in the same order (the build disables FMA
// contraction), so the SIMD forms agree with the twin bit for bit, including on edges
// (u = 0, v = 0, u + v = 1 count as hits) and for rays parallel to the plane (det = 0 misses).
#include <cstdint>

#include "ray1.h"
#include "simd.h"
#include "triangle_block.h"

namespace foton::kern {

// Returns true and writes t, u, v when the ray hits the triangle with tmin < t < tmax.
inline bool intersect_triangle_scalar(const Ray1& r, float v0x, float v0y, float v0z, float e1x,
                                      float e1y, float e1z, float e2x, float e2y, float e2z,
                                      float tmax, float& t_out, float& u_out, float& v_out) {
    const float px = r.dy * e2z - r.dz * e2y;
    const float py = r.dz * e2x - r.dx * e2z;
    const float pz = r.dx * e2y - r.dy * e2x;
    const float det = e1x * px + e1y * py + e1z * pz;
    const float inv = 1.f / det;
    const float tx = r.ox - v0x, ty = r.oy - v0y, tz = r.oz - v0z;
    const float u = (tx * px + ty * py + tz * pz) * inv;
    const float qx = ty * e1z - tz * e1y;
    const float qy = tz * e1x - tx * e1z;
    const float qz = tx * e1y - ty * e1x;
    const float v = (r.dx * qx + r.dy * qy + r.dz * qz) * inv;
    const float t = (e2x * qx + e2y * qy + e2z * qz) * inv;
    const bool hit = det != 0.f && u >= 0.f && v >= 0.f && u + v <= 1.f && t > r.tmin && t < tmax;
    if (hit) {
        t_out = t;
        u_out = u;
        v_out = v;
    }
    return hit;
}

// Scalar twin of intersect_block: the lanes in order, keeping the strictly closer hit.
inline bool intersect_block_scalar(const Ray1& r, const TriangleBlock& b, TriHit& hit) {
    bool any = false;
    for (std::size_t i = 0; i < kBlockWidth; ++i) {
        float t, u, v;
        if (intersect_triangle_scalar(r, b.v0x[i], b.v0y[i], b.v0z[i], b.e1x[i], b.e1y[i], b.e1z[i],
                                      b.e2x[i], b.e2y[i], b.e2z[i], hit.t, t, u, v)) {
            hit = TriHit{t, u, v, b.id[i]};
            any = true;
        }
    }
    return any;
}

// Scalar twin of occluded_block.
inline bool occluded_block_scalar(const Ray1& r, const TriangleBlock& b) {
    for (std::size_t i = 0; i < kBlockWidth; ++i) {
        float t, u, v;
        if (intersect_triangle_scalar(r, b.v0x[i], b.v0y[i], b.v0z[i], b.e1x[i], b.e1y[i], b.e1z[i],
                                      b.e2x[i], b.e2y[i], b.e2z[i], r.tmax, t, u, v))
            return true;
    }
    return false;
}

namespace detail {
using simd::FloatV;
using simd::MaskV;

template <class V>
struct BlockTestT {
    V t, u, v;
    typename V::batch_bool_type hit;
};
using BlockTest = BlockTestT<FloatV>;

template <class V>
struct TriVT {
    V v0x, v0y, v0z, e1x, e1y, e1z, e2x, e2y, e2z;
};
using TriV = TriVT<FloatV>;

template <class V, std::size_t M>
inline TriVT<V> load_block(const TriangleBlockT<M>& b) {
    static_assert(V::size == M);
    return {V::load_aligned(b.v0x), V::load_aligned(b.v0y), V::load_aligned(b.v0z),
            V::load_aligned(b.e1x), V::load_aligned(b.e1y), V::load_aligned(b.e1z),
            V::load_aligned(b.e2x), V::load_aligned(b.e2y), V::load_aligned(b.e2z)};
}
inline TriV load_block(const TriangleBlock& b) {
    return load_block<FloatV>(b);
}

// One triangle of a block (lane `l`) broadcast to every lane: for a packet of rays against it.
template <class V, std::size_t M>
inline TriVT<V> broadcast_lane(const TriangleBlockT<M>& b, std::size_t l) {
    return {V(b.v0x[l]), V(b.v0y[l]), V(b.v0z[l]), V(b.e1x[l]), V(b.e1y[l]),
            V(b.e1z[l]), V(b.e2x[l]), V(b.e2y[l]), V(b.e2z[l])};
}

// The one Möller–Trumbore expression sequence every shape and width evaluates; the scalar
// twin above spells out the same operations in the same order.
template <class V>
inline BlockTestT<V> test(const V& ox, const V& oy, const V& oz, const V& dx, const V& dy,
                          const V& dz, const V& tmin, const V& tmax, const TriVT<V>& tri) {
    const V px = dy * tri.e2z - dz * tri.e2y;
    const V py = dz * tri.e2x - dx * tri.e2z;
    const V pz = dx * tri.e2y - dy * tri.e2x;
    const V det = tri.e1x * px + tri.e1y * py + tri.e1z * pz;
    const V inv = V(1.f) / det;
    const V tx = ox - tri.v0x;
    const V ty = oy - tri.v0y;
    const V tz = oz - tri.v0z;
    const V u = (tx * px + ty * py + tz * pz) * inv;
    const V qx = ty * tri.e1z - tz * tri.e1y;
    const V qy = tz * tri.e1x - tx * tri.e1z;
    const V qz = tx * tri.e1y - ty * tri.e1x;
    const V v = (dx * qx + dy * qy + dz * qz) * inv;
    const V t = (tri.e2x * qx + tri.e2y * qy + tri.e2z * qz) * inv;
    const V zero(0.f), one(1.f);
    const auto hit =
        (det != zero) & (u >= zero) & (v >= zero) & (u + v <= one) & (t > tmin) & (t < tmax);
    return {t, u, v, hit};
}
}  // namespace detail

// One ray against the lanes of a block set in `lanes`. Updates `hit` (whose t is the current
// tmax) with the closest hit; ties go to the lowest lane. Returns true when it improved `hit`.
inline bool intersect_block(const Ray1& r, const TriangleBlock& b, TriHit& hit, uint32_t lanes) {
    using simd::FloatV;
    const detail::BlockTest bt =
        detail::test(FloatV(r.ox), FloatV(r.oy), FloatV(r.oz), FloatV(r.dx), FloatV(r.dy),
                     FloatV(r.dz), FloatV(r.tmin), FloatV(hit.t), detail::load_block(b));
    uint32_t bits = simd::movemask(bt.hit) & lanes;
    if (bits == 0) return false;
    alignas(64) float ts[kBlockWidth];
    bt.t.store_aligned(ts);
    uint32_t best = static_cast<uint32_t>(__builtin_ctz(bits));
    for (bits &= bits - 1; bits != 0; bits &= bits - 1) {
        const uint32_t lane = static_cast<uint32_t>(__builtin_ctz(bits));
        if (ts[lane] < ts[best]) best = lane;
    }
    alignas(64) float us[kBlockWidth], vs[kBlockWidth];
    bt.u.store_aligned(us);
    bt.v.store_aligned(vs);
    hit = TriHit{ts[best], us[best], vs[best], b.id[best]};
    return true;
}

// One ray against all W triangles of a block.
inline bool intersect_block(const Ray1& r, const TriangleBlock& b, TriHit& hit) {
    return intersect_block(r, b, hit, ~0u);
}

// Any hit with tmin < t < tmax in the block (shadow rays).
inline bool occluded_block(const Ray1& r, const TriangleBlock& b) {
    using simd::FloatV;
    const detail::BlockTest bt =
        detail::test(FloatV(r.ox), FloatV(r.oy), FloatV(r.oz), FloatV(r.dx), FloatV(r.dy),
                     FloatV(r.dz), FloatV(r.tmin), FloatV(r.tmax), detail::load_block(b));
    return xsimd::any(bt.hit);
}

// A packet of W rays in SoA form against one triangle; the hit columns are updated in place
// where the triangle is closer than the current t (which acts as each ray's tmax).
struct alignas(64) RayPacket {
    float ox[kBlockWidth], oy[kBlockWidth], oz[kBlockWidth];
    float dx[kBlockWidth], dy[kBlockWidth], dz[kBlockWidth];
    float tmin[kBlockWidth];
};
struct alignas(64) PacketHits {
    float t[kBlockWidth], u[kBlockWidth], v[kBlockWidth];
    uint32_t id[kBlockWidth];
};

inline uint32_t intersect_packet(const RayPacket& p, const TriangleBlock& tri_block,
                                 std::size_t lane, PacketHits& h) {
    using simd::FloatV;
    const detail::TriV tri = detail::broadcast_lane<FloatV>(tri_block, lane);
    const FloatV tcur = FloatV::load_aligned(h.t);
    const detail::BlockTest bt = detail::test(
        FloatV::load_aligned(p.ox), FloatV::load_aligned(p.oy), FloatV::load_aligned(p.oz),
        FloatV::load_aligned(p.dx), FloatV::load_aligned(p.dy), FloatV::load_aligned(p.dz),
        FloatV::load_aligned(p.tmin), tcur, tri);
    const uint32_t bits = simd::movemask(bt.hit);
    if (bits == 0) return 0;
    xsimd::select(bt.hit, bt.t, tcur).store_aligned(h.t);
    xsimd::select(bt.hit, bt.u, FloatV::load_aligned(h.u)).store_aligned(h.u);
    xsimd::select(bt.hit, bt.v, FloatV::load_aligned(h.v)).store_aligned(h.v);
    const uint32_t id = tri_block.id[lane];
    for (uint32_t b = bits; b != 0; b &= b - 1) h.id[__builtin_ctz(b)] = id;
    return bits;
}

}  // namespace foton::kern
