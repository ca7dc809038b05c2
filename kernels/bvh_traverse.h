#pragma once
// Single-ray traversal of TriangleBvhT (included by triangle_bvh.h): the hot loops.
#include <cmath>
#include <cstring>

#include "bvh_box_ray.h"

namespace foton::kern {

namespace bvh_detail {

// The ray broadcast to M lanes for the leaf blocks.
template <std::size_t M>
struct LeafRay {
    using V = simd::FloatW<M>;
    V ox, oy, oz, dx, dy, dz, tmin;
    LeafRay() = default;
    explicit LeafRay(const Ray1& r)
        : ox(r.ox), oy(r.oy), oz(r.oz), dx(r.dx), dy(r.dy), dz(r.dz), tmin(r.tmin) {}
};

// nextafter(t, +inf) without the libm call (it sits in the leaf loop): the next float up.
inline float next_up(float t) {
    if (!(t < kInf)) return t;  // +inf and NaN stay
    if (t == 0.f) return 0x1p-149f;
    uint32_t b;
    std::memcpy(&b, &t, sizeof b);
    b = t > 0.f ? b + 1 : b - 1;
    std::memcpy(&t, &b, sizeof t);
    return t;
}

// Closest hit among a leaf's blocks; the least (t, id) wins, as in brute force by id.
template <std::size_t M>
inline bool leaf_closest(const LeafRay<M>& lr, const TriangleBlockT<M>* blocks, uint32_t count,
                         TriHit& hit) {
    using V = simd::FloatW<M>;
    bool improved = false;
    for (uint32_t k = 0; k < count; ++k) {
        const TriangleBlockT<M>& b = blocks[k];
        // t <= hit.t once there is a hit (a tie may still win on id), t < tmax before.
        const float bound = hit.valid() ? next_up(hit.t) : hit.t;
        const auto bt = detail::test<V>(lr.ox, lr.oy, lr.oz, lr.dx, lr.dy, lr.dz, lr.tmin, V(bound),
                                        detail::load_block<V>(b));
        uint32_t bits = simd::movemask(bt.hit);
        if (bits == 0) continue;
        alignas(64) float ts[M];
        bt.t.store_aligned(ts);
        do {
            const uint32_t lane = uint32_t(__builtin_ctz(bits));
            bits &= bits - 1;
            const float t = ts[lane];
            const uint32_t id = b.id[lane];
            if (t < hit.t || (t == hit.t && id < hit.id)) {
                alignas(64) float us[M], vs[M];
                bt.u.store_aligned(us);
                bt.v.store_aligned(vs);
                hit = TriHit{t, us[lane], vs[lane], id};
                improved = true;
            }
        } while (bits);
    }
    return improved;
}

template <std::size_t M>
inline bool leaf_any(const LeafRay<M>& lr, const TriangleBlockT<M>* blocks, uint32_t count,
                     float tmax) {
    using V = simd::FloatW<M>;
    for (uint32_t k = 0; k < count; ++k) {
        const auto bt = detail::test<V>(lr.ox, lr.oy, lr.oz, lr.dx, lr.dy, lr.dz, lr.tmin, V(tmax),
                                        detail::load_block<V>(blocks[k]));
        if (simd::movemask(bt.hit)) return true;
    }
    return false;
}

// The single-ray walks over a tree's arrays. Free functions of plain pointers, so that no
// store to the hit or the stack can alias the tree's base pointers (members of `this` were
// reloaded at every node); kCount false compiles the statistics out, three registers fewer.
template <bool kCount, std::size_t N, std::size_t M>
bool closest_walk(const WideNode<N>* nodes, const TriangleBlockT<M>* blocks, uint32_t start,
                  const Ray1& r, TriHit& hit, BvhCounters* counters) {
    using V = simd::FloatW<N>;
    const BoxRay<N> br(r);
    const LeafRay<M> lr(r);
    StackEntry stack[kStackSize];
    uint32_t sp = 0;
    uint32_t ref = start;
    bool found = false;
    float tcull = hit.valid() ? hit.t * kBvhCullScale : hit.t;
    uint64_t n_nodes = 0, n_leaves = 0, n_blocks = 0;
    for (;;) {
        // Descend until a leaf.
        while (!bvh_is_leaf(ref)) {
            const WideNode<N>& node = nodes[ref];
            if constexpr (kCount) ++n_nodes;
            V tnv;
            uint32_t mask = br.test(node, tcull, tnv);
            if (mask == 0) goto pop;
            alignas(64) float tn[N];
            tnv.store_aligned(tn);
            ref = order_children(node, mask, tn, stack, sp);
        }
        // Leaf.
        if constexpr (kCount) {
            ++n_leaves;
            n_blocks += bvh_leaf_blocks(ref);
        }
        if (leaf_closest<M>(lr, &blocks[bvh_leaf_first(ref)], bvh_leaf_blocks(ref), hit)) {
            found = true;
            tcull = hit.t * kBvhCullScale;
        }
    pop:
        for (;;) {
            if (sp == 0) goto done;
            const StackEntry& e = stack[--sp];
            if (e.t <= tcull) {
                ref = e.ref;
                break;
            }
        }
    }
done:
    if constexpr (kCount) add_counts(counters, n_nodes, n_leaves, n_blocks);
    return found;
}

template <bool kCount, std::size_t N, std::size_t M>
bool any_walk(const WideNode<N>* nodes, const TriangleBlockT<M>* blocks, uint32_t start,
              const Ray1& r, BvhCounters* counters) {
    using V = simd::FloatW<N>;
    const BoxRay<N> br(r);
    const LeafRay<M> lr(r);
    uint32_t stack[kStackSize];
    std::size_t sp = 0;
    uint32_t ref = start;
    bool hit = false;
    uint64_t n_nodes = 0, n_leaves = 0, n_blocks = 0;
    for (;;) {
        while (!bvh_is_leaf(ref)) {
            const WideNode<N>& node = nodes[ref];
            if constexpr (kCount) ++n_nodes;
            V tnv;
            uint32_t mask = br.test(node, r.tmax, tnv);
            if (mask == 0) goto pop;
            ref = node.child[__builtin_ctz(mask)];
            for (mask &= mask - 1; mask; mask &= mask - 1)
                stack[sp++] = node.child[__builtin_ctz(mask)];
        }
        if constexpr (kCount) {
            ++n_leaves;
            n_blocks += bvh_leaf_blocks(ref);
        }
        if (leaf_any<M>(lr, &blocks[bvh_leaf_first(ref)], bvh_leaf_blocks(ref), r.tmax)) {
            hit = true;
            break;
        }
    pop:
        if (sp == 0) break;
        ref = stack[--sp];
    }
    if constexpr (kCount) add_counts(counters, n_nodes, n_leaves, n_blocks);
    return hit;
}

}  // namespace bvh_detail

template <std::size_t N, std::size_t M>
bool TriangleBvhT<N, M>::intersect(const Ray1& r, TriHit& hit, BvhCounters* counters) const {
    if (root_ == kBvhEmpty || bvh_detail::unusable(r)) return false;
    if (r.tmax < hit.t) hit.t = r.tmax;
    return closest_from(root_, r, hit, counters);
}

template <std::size_t N, std::size_t M>
bool TriangleBvhT<N, M>::closest_from(uint32_t start, const Ray1& r, TriHit& hit,
                                      BvhCounters* counters) const {
    if (counters)
        return bvh_detail::closest_walk<true>(nodes_.data(), blocks_.data(), start, r, hit,
                                              counters);
    return bvh_detail::closest_walk<false>(nodes_.data(), blocks_.data(), start, r, hit, nullptr);
}

template <std::size_t N, std::size_t M>
bool TriangleBvhT<N, M>::occluded(const Ray1& r, BvhCounters* counters) const {
    if (root_ == kBvhEmpty || bvh_detail::unusable(r)) return false;
    return any_from(root_, r, counters);
}

template <std::size_t N, std::size_t M>
bool TriangleBvhT<N, M>::any_from(uint32_t start, const Ray1& r, BvhCounters* counters) const {
    if (counters)
        return bvh_detail::any_walk<true>(nodes_.data(), blocks_.data(), start, r, counters);
    return bvh_detail::any_walk<false>(nodes_.data(), blocks_.data(), start, r, nullptr);
}

}  // namespace foton::kern
