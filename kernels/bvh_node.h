#pragma once
// The wide BVH's memory layout. A node holds the boxes of its N children in SoA rows, so one
// SIMD slab test (N lanes) tests them all; a child reference is an inner node's index or a leaf
// (a run of SIMD triangle blocks). Empty child slots have inverted, infinite boxes that every
// ray misses, so the test needs no mask.
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "ray1.h"

namespace foton::kern {

// N = children per node, the lanes of one box test. 8 (AVX) was faster than 4 and 16 on the
// AVX-512 development machine (bench/bench_traversal.cpp, bvh variants); builds without AVX
// use 4.
template <std::size_t N>
struct alignas(64) WideNode {
    // Rows: lo x, hi x, lo y, hi y, lo z, hi z. A ray reads row 2a + (d_a < 0) as the near
    // plane of axis a and the other one as the far plane, so no min/max sorts the slabs.
    float bounds[6][N];
    uint32_t child[N];
};

// Child references.
//   inner: the node index (bit 31 clear);
//   leaf:  bit 31 set, bits 27..30 the number of triangle blocks minus one, bits 0..26 the
//          first block.
inline constexpr uint32_t kBvhLeafFlag = 0x80000000u;
inline constexpr uint32_t kBvhMaxLeafBlocks = 16;
inline constexpr uint32_t kBvhMaxFirstBlock = (1u << 27) - 1;
inline constexpr uint32_t kBvhEmpty = 0xffffffffu;  // a tree without primitives

inline bool bvh_is_leaf(uint32_t ref) {
    return (ref & kBvhLeafFlag) != 0;
}
inline uint32_t bvh_leaf_first(uint32_t ref) {
    return ref & kBvhMaxFirstBlock;
}
inline uint32_t bvh_leaf_blocks(uint32_t ref) {
    return ((ref >> 27) & 15u) + 1;
}
inline uint32_t bvh_make_leaf(uint32_t first_block, uint32_t blocks) {
    return kBvhLeafFlag | ((blocks - 1) << 27) | first_block;
}

// What a traversal did, for --stats and the benchmarks' per-ray tables.
struct BvhCounters {
    uint64_t nodes = 0;   // wide nodes whose N boxes were tested
    uint64_t leaves = 0;  // leaves visited
    uint64_t blocks = 0;  // triangle blocks tested (M ray/triangle tests each)
};

// A traversal counts in locals and adds them once at the end (the counters are optional).
inline void add_counts(BvhCounters* c, uint64_t nodes, uint64_t leaves, uint64_t blocks) {
    if (!c) return;
    c->nodes += nodes;
    c->leaves += leaves;
    c->blocks += blocks;
}

// Far slab distances use 1 / d scaled by this, which makes the box test conservative: with
// t = (b - o) * (1 / d) in floats, near and far can each be off by gamma(3) relative (Ize 2013,
// "Robust BVH ray traversal"); the margin here is twice what that needs, so that the scaling's
// own rounding is covered too. A box missed by rounding would lose a hit.
inline constexpr float kBvhFarScale = 1.f + 4.f * (3.f * 0x1p-24f) / (1.f - 3.f * 0x1p-24f);

// Once a hit at t is found, boxes entered after t * kBvhCullScale are skipped. The margin is
// not for speed but for the canonical answer: a triangle hit at the same t (a shared vertex or
// edge) may have a box whose computed entry lies an ulp or two past that t, and it must still
// be tested so that the smaller id wins, as in brute force.
inline constexpr float kBvhCullScale = 1.f + 0x1p-16f;

// The scalar slab test of a box against a ray (1 / d given): the arithmetic and NaN handling of
// the SIMD node test, for the scalar twin and the binary trees. The entry distance in `tnear`.
inline bool slab_test_scalar(const float lo[3], const float hi[3], const float o[3],
                             const float inv[3], float tmin, float tmax, float& tnear) {
    float tn = tmin, tf = tmax;
    for (int a = 2; a >= 0; --a) {
        const bool neg = std::signbit(inv[a]);
        const float t0 = ((neg ? hi : lo)[a] - o[a]) * inv[a];
        const float t1 = ((neg ? lo : hi)[a] - o[a]) * (inv[a] * kBvhFarScale);
        tn = t0 > tn ? t0 : tn;  // NaN drops out
        tf = t1 < tf ? t1 : tf;
    }
    tnear = tn;
    return tn <= tf;
}

// Widens a box by about 8 ulps of its largest coordinate. Möller–Trumbore works in floats, and
// a ray whose direction has a component far below an ulp of the origin (1e-20 next to 0.1, say)
// stays on its starting plane in that arithmetic: it "hits" a triangle of a box that the exact
// slab test says it left at t = 0. The pad keeps the box test at least as generous as the
// triangle test, so the BVH finds what brute force finds.
inline void pad_box(float lo[3], float hi[3]) {
    float m = 0.f;
    for (int a = 0; a < 3; ++a) m = std::max({m, std::fabs(lo[a]), std::fabs(hi[a])});
    const float pad = m * 0x1p-20f;
    for (int a = 0; a < 3; ++a) lo[a] -= pad, hi[a] += pad;
}

// Zero direction components are kept: 1 / d is then +-inf, a slab the ray lies in gives
// (b - o) * inf = NaN, and the box test's min/max chains ignore NaN, which is the right answer
// (a ray exactly in a face plane is inside that slab for its whole length). Replacing d by a
// tiny epsilon instead would put such a ray just outside the box.

}  // namespace foton::kern
