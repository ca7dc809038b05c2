#pragma once
// What every single-ray walk of a wide BVH shares (triangles in bvh_traverse.h, curves in
// curve_bvh.cpp): the ray prepared for one SIMD test of a node's N boxes, the traversal stack,
// and the children's front-to-back order.
#include <cmath>
#include <cstdint>

#include "bvh_node.h"
#include "ray1.h"
#include "simd.h"

namespace foton::kern {

namespace bvh_detail {

// A ray prepared for box tests: origin and reciprocal direction broadcast to N lanes, and the
// row offsets of the near planes per axis. A far row is its near row with bit N flipped (rows
// 2a and 2a + 1 hold axis a's low and high planes), so the far offsets are derived, not kept.
// (GCC hoists the three XORs out of the walk; the register pressure docs/kernels.md describes
// came from the znver3 tuning, not from these offsets.)
template <std::size_t N>
struct BoxRay {
    using V = simd::FloatW<N>;
    V ox, oy, oz, ix, iy, iz, fx, fy, fz, tmin;  // i: 1 / d for near planes; f: scaled, far
    uint32_t near_x, near_y, near_z;             // float offsets into Node::bounds

    BoxRay() = default;
    explicit BoxRay(const Ray1& r) {
        const float inv[3] = {1.f / r.dx, 1.f / r.dy, 1.f / r.dz};
        ox = V(r.ox), oy = V(r.oy), oz = V(r.oz);
        ix = V(inv[0]), iy = V(inv[1]), iz = V(inv[2]);
        fx = V(inv[0] * kBvhFarScale), fy = V(inv[1] * kBvhFarScale), fz = V(inv[2] * kBvhFarScale);
        tmin = V(r.tmin);
        near_x = uint32_t((0 + std::signbit(inv[0])) * N);
        near_y = uint32_t((2 + std::signbit(inv[1])) * N);
        near_z = uint32_t((4 + std::signbit(inv[2])) * N);
    }
    static constexpr uint32_t far_of(uint32_t near) { return near ^ uint32_t(N); }
    uint32_t far_x() const { return far_of(near_x); }
    uint32_t far_y() const { return far_of(near_y); }
    uint32_t far_z() const { return far_of(near_z); }

    // Lanes whose box the ray enters within [tmin, tcur]; their entry distances in `tn`. The
    // chains keep a non-NaN value innermost, so a NaN slab (see bvh_node.h) drops out.
    // Always inlined: GCC kept it out of line, a call per node.
    [[gnu::always_inline]] uint32_t test(const WideNode<N>& node, float tcur, V& tn) const {
        const float* b = &node.bounds[0][0];
        const V tnx = (V::load_aligned(b + near_x) - ox) * ix;
        const V tny = (V::load_aligned(b + near_y) - oy) * iy;
        const V tnz = (V::load_aligned(b + near_z) - oz) * iz;
        const V tfx = (V::load_aligned(b + far_x()) - ox) * fx;
        const V tfy = (V::load_aligned(b + far_y()) - oy) * fy;
        const V tfz = (V::load_aligned(b + far_z()) - oz) * fz;
        tn = simd::vmax(tnx, simd::vmax(tny, simd::vmax(tnz, tmin)));
        const V tf = simd::vmin(tfx, simd::vmin(tfy, simd::vmin(tfz, V(tcur))));
        return simd::movemask(tn <= tf);
    }
};

// Rays the box test cannot order (NaN anywhere) or that have nothing to find.
inline bool unusable(const Ray1& r) {
    return std::isnan(r.ox + r.oy + r.oz + r.dx + r.dy + r.dz) || !(r.tmin < r.tmax) ||
           (r.dx == 0.f && r.dy == 0.f && r.dz == 0.f);
}

struct StackEntry {
    uint32_t ref;
    float t;
};

// The stack holds at most N - 1 entries per level; build depth is bounded (bvh_build.cpp).
inline constexpr std::size_t kStackSize = 1024;

// Pushes the children in `mask` (entry distances tn) and returns the nearest, leaving the
// others on the stack far to near: the single-ray kernel's order.
// Always inlined: out of line, GCC spilled and reloaded the ray's registers around every call.
template <std::size_t N>
[[gnu::always_inline]] inline uint32_t order_children(const WideNode<N>& node, uint32_t mask,
                                                      const float* tn, StackEntry* stack,
                                                      uint32_t& sp) {
    const uint32_t c0 = uint32_t(__builtin_ctz(mask));
    mask &= mask - 1;
    if (mask == 0) return node.child[c0];
    const uint32_t c1 = uint32_t(__builtin_ctz(mask));
    mask &= mask - 1;
    if (mask == 0) {
        if (tn[c0] <= tn[c1]) {
            stack[sp++] = {node.child[c1], tn[c1]};
            return node.child[c0];
        }
        stack[sp++] = {node.child[c0], tn[c0]};
        return node.child[c1];
    }
    const uint32_t first = sp;
    stack[sp++] = {node.child[c0], tn[c0]};
    stack[sp++] = {node.child[c1], tn[c1]};
    do {
        const uint32_t c = uint32_t(__builtin_ctz(mask));
        mask &= mask - 1;
        stack[sp++] = {node.child[c], tn[c]};
    } while (mask);
    for (uint32_t i = first + 1; i < sp; ++i) {
        const StackEntry e = stack[i];
        uint32_t j = i;
        for (; j > first && stack[j - 1].t < e.t; --j) stack[j] = stack[j - 1];
        stack[j] = e;
    }
    return stack[--sp].ref;
}

}  // namespace bvh_detail

}  // namespace foton::kern
