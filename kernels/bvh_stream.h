#pragma once
// Stream traversal of TriangleBvhT (included by triangle_bvh.h): a whole batch of incoherent
// rays (diffuse bounces, shadow rays, photons, final-gather rays) in one call, in one of two
// modes (StreamMode, triangle_bvh.h).
//
// Interleaved. On incoherent rays the single-ray kernel waits on memory: each step loads a
// node or a leaf that the previous step chose, so the loads form one dependent chain (on the
// bunny the first load of a node and of a leaf block each hold 12 % of the kernel's samples,
// docs/kernels.md). What helps is memory-level parallelism. The kernel keeps kStreamSlots rays
// in flight and steps them in turn, one node or leaf each. A step ends by choosing the ray's
// next node and prefetching it. By the time the other rays have taken their steps and this ray
// comes round again, the node is usually in cache. (This is the "asynchronous memory access
// chaining" of database hash probes, Kocberber et al. 2015, applied to BVH traversal.) Each
// ray takes exactly the steps of its single-ray traversal (closest_from / any_from): the same
// node tests, the same order, the same culling. So every ray gets exactly the hit that
// intersect() / occluded() return for it, and the same counters.
//
// Sorted packets. Rays ordered by direction octant and origin, then W consecutive rays of that
// order traced by the packet kernel (bvh_packet.h), which gives every ray its single-ray
// answer. For batches whose coherence the given order hides (the shadow rays of an image tile
// to several lights); on rays from random points of a whole mesh it does not pay.
//
// The tests hold both modes to the single-ray forms (tests/test_bvh_stream.cpp).
#include <vector>

#include "bvh_traverse.h"
#include "ray_stream.h"

namespace foton::kern {

namespace bvh_detail {

// Rays in flight. 4, 8 and 16 were measured (bunny and dragon, diffuse and shadow rays, two
// alternating runs; docs/kernels.md): none was consistently faster within the noise, so 8.
inline constexpr std::size_t kStreamSlots = 8;

inline void prefetch_bytes(const void* p, std::size_t bytes) {
    const char* c = static_cast<const char*>(p);
    for (std::size_t o = 0; o < bytes; o += 64) __builtin_prefetch(c + o);
}

// The memory a reference's step will read: a node, or a leaf's blocks (at most two: the default
// build makes leaves of one block; longer leaves stream in behind the first two).
template <std::size_t N, std::size_t M>
inline void prefetch_ref(const WideNode<N>* nodes, const TriangleBlockT<M>* blocks, uint32_t ref) {
    if (!bvh_is_leaf(ref)) {
        prefetch_bytes(nodes + ref, sizeof(WideNode<N>));
        return;
    }
    const uint32_t n = bvh_leaf_blocks(ref) < 2 ? bvh_leaf_blocks(ref) : 2;
    prefetch_bytes(blocks + bvh_leaf_first(ref), n * sizeof(TriangleBlockT<M>));
}

// One ray between two steps. The box and leaf forms of the ray are those of the single-ray
// kernel, built once when the ray enters its slot.
template <std::size_t N, std::size_t M>
struct StreamSlot {
    BoxRay<N> box;
    LeafRay<M> leaf;
    TriHit hit;
    float tcull = 0.f;   // closest hit: the cull distance; any hit: tmax
    uint32_t ref = 0;    // the node or leaf of the next step
    uint32_t sp = 0;     // entries on this slot's stack
    uint32_t index = 0;  // the ray's index in the stream

    // Ray r (index i of the stream) starts at the root with an empty stack; the caller sets
    // hit and tcull, which differ between closest and any hit.
    void start(const Ray1& r, uint32_t root, std::size_t i) {
        box = BoxRay<N>(r);
        leaf = LeafRay<M>(r);
        ref = root;
        sp = 0;
        index = uint32_t(i);
    }
};

struct StreamCounts {
    uint64_t nodes = 0, leaves = 0, blocks = 0;
};

// One step of a closest-hit traversal: the node or leaf at s.ref. Chooses and prefetches the
// next one; returns false when the ray is done.
template <std::size_t N, std::size_t M>
inline bool closest_step(const WideNode<N>* nodes, const TriangleBlockT<M>* blocks,
                         StreamSlot<N, M>& s, StackEntry* stack, StreamCounts& c) {
    using V = simd::FloatW<N>;
    if (!bvh_is_leaf(s.ref)) {
        const WideNode<N>& node = nodes[s.ref];
        ++c.nodes;
        V tnv;
        const uint32_t mask = s.box.test(node, s.tcull, tnv);
        if (mask != 0) {
            alignas(64) float tn[N];
            tnv.store_aligned(tn);
            s.ref = order_children(node, mask, tn, stack, s.sp);
            prefetch_ref(nodes, blocks, s.ref);
            return true;
        }
    } else {
        ++c.leaves;
        c.blocks += bvh_leaf_blocks(s.ref);
        if (leaf_closest<M>(s.leaf, blocks + bvh_leaf_first(s.ref), bvh_leaf_blocks(s.ref), s.hit))
            s.tcull = s.hit.t * kBvhCullScale;
    }
    while (s.sp != 0) {
        const StackEntry& e = stack[--s.sp];
        if (e.t <= s.tcull) {
            s.ref = e.ref;
            prefetch_ref(nodes, blocks, s.ref);
            return true;
        }
    }
    return false;
}

// One step of an any-hit traversal; returns false when the ray is done (s.hit.id is then 0
// for occluded, kInvalidId for not).
template <std::size_t N, std::size_t M>
inline bool any_step(const WideNode<N>* nodes, const TriangleBlockT<M>* blocks, StreamSlot<N, M>& s,
                     uint32_t* stack, StreamCounts& c) {
    using V = simd::FloatW<N>;
    if (!bvh_is_leaf(s.ref)) {
        const WideNode<N>& node = nodes[s.ref];
        ++c.nodes;
        V tnv;
        uint32_t mask = s.box.test(node, s.tcull, tnv);
        if (mask != 0) {
            s.ref = node.child[__builtin_ctz(mask)];
            for (mask &= mask - 1; mask; mask &= mask - 1) {
                const uint32_t child = node.child[__builtin_ctz(mask)];
                stack[s.sp++] = child;
            }
            prefetch_ref(nodes, blocks, s.ref);
            return true;
        }
    } else {
        ++c.leaves;
        c.blocks += bvh_leaf_blocks(s.ref);
        if (leaf_any<M>(s.leaf, blocks + bvh_leaf_first(s.ref), bvh_leaf_blocks(s.ref), s.tcull)) {
            s.hit.id = 0;
            return false;
        }
    }
    if (s.sp == 0) return false;
    s.ref = stack[--s.sp];
    prefetch_ref(nodes, blocks, s.ref);
    return true;
}

// 10 bits of x spread to every third bit.
inline uint32_t spread_bits3(uint32_t x) {
    x &= 0x3ffu;
    x = (x | (x << 16)) & 0x030000ffu;
    x = (x | (x << 8)) & 0x0300f00fu;
    x = (x | (x << 4)) & 0x030c30c3u;
    x = (x | (x << 2)) & 0x09249249u;
    return x;
}

// The order of a sorted stream: by direction octant, then by the Morton code of the origin in
// the tree's bounds (9 bits per axis), so that consecutive rays start close and head the same
// way, and a packet of them takes one path through the tree. An LSD
// radix sort of (key, index) pairs on the key's 30 bits: linear in the batch, a few per cent
// of tracing it. `order` receives the ray indices.
inline void stream_order(const RayStream& rays, const float lo[3], const float hi[3],
                         std::vector<uint64_t>& keys, std::vector<uint64_t>& tmp,
                         std::vector<uint32_t>& order) {
    const std::size_t n = rays.count;
    keys.resize(n);
    tmp.resize(n);
    float scale[3];
    for (int a = 0; a < 3; ++a) scale[a] = hi[a] > lo[a] ? 511.99f / (hi[a] - lo[a]) : 0.f;
    for (std::size_t i = 0; i < n; ++i) {
        auto cell = [&](float v, int a) {
            const float c = (v - lo[a]) * scale[a];
            return uint32_t(c > 0.f ? (c < 511.f ? c : 511.f) : 0.f);  // NaN -> 0
        };
        const uint32_t morton = spread_bits3(cell(rays.ox[i], 0)) |
                                (spread_bits3(cell(rays.oy[i], 1)) << 1) |
                                (spread_bits3(cell(rays.oz[i], 2)) << 2);
        const uint32_t octant = uint32_t(std::signbit(rays.dx[i])) |
                                uint32_t(std::signbit(rays.dy[i])) << 1 |
                                uint32_t(std::signbit(rays.dz[i])) << 2;
        keys[i] = (uint64_t(octant << 27 | morton) << 32) | i;
    }
    for (int shift = 32; shift < 62; shift += 8) {
        uint32_t count[257] = {};
        for (std::size_t i = 0; i < n; ++i) ++count[((keys[i] >> shift) & 255u) + 1];
        for (int d = 0; d < 256; ++d) count[d + 1] += count[d];
        for (std::size_t i = 0; i < n; ++i) tmp[count[(keys[i] >> shift) & 255u]++] = keys[i];
        keys.swap(tmp);
    }
    order.resize(n);
    for (std::size_t i = 0; i < n; ++i) order[i] = uint32_t(keys[i]);
}

// Runs `step` over the stream with kStreamSlots rays in flight: `begin(slot, i)` puts ray i in
// a slot (false: the ray needs no traversal and was answered), `finish(slot)` answers a ray
// that is done.
template <class Slot, class Begin, class Step, class Finish>
inline void run_stream(std::size_t count, Slot* slots, Begin&& begin, Step&& step,
                       Finish&& finish) {
    uint32_t live[kStreamSlots];
    std::size_t n_live = 0, next = 0;
    auto refill = [&](uint32_t k) {
        while (next < count)
            if (begin(slots[k], next++)) return true;
        return false;
    };
    for (uint32_t k = 0; k < kStreamSlots; ++k)
        if (refill(k)) live[n_live++] = k;
    while (n_live != 0) {
        for (std::size_t j = 0; j < n_live;) {
            const uint32_t k = live[j];
            if (step(k)) {
                ++j;
                continue;
            }
            finish(slots[k]);
            if (refill(k)) {
                ++j;
                continue;
            }
            live[j] = live[--n_live];
        }
    }
}

}  // namespace bvh_detail

template <std::size_t N, std::size_t M>
const uint32_t* TriangleBvhT<N, M>::stream_order_of(const RayStream& rays) const {
    // Per thread, so that a stream call allocates nothing once warm.
    thread_local std::vector<uint64_t> keys, tmp;
    thread_local std::vector<uint32_t> order;
    bvh_detail::stream_order(rays, bounds_lo_, bounds_hi_, keys, tmp, order);
    return order.data();
}

template <std::size_t N, std::size_t M>
void TriangleBvhT<N, M>::intersect_stream(const RayStream& rays, const HitStream& out,
                                          BvhCounters* counters, StreamMode mode) const {
    using namespace bvh_detail;
    if (mode == StreamMode::SortedPackets) return intersect_sorted_packets(rays, out, counters);
    using Slot = StreamSlot<N, M>;
    Slot slots[kStreamSlots];
    StackEntry stacks[kStreamSlots][kStackSize];
    StreamCounts c;
    auto begin = [&](Slot& s, std::size_t i) {
        const Ray1 r = rays.ray(i);
        TriHit h;
        if (root_ == kBvhEmpty || unusable(r)) {
            out.set(i, h);
            return false;
        }
        if (r.tmax < h.t) h.t = r.tmax;
        s.start(r, root_, i);
        s.hit = h;
        s.tcull = h.t;
        return true;
    };
    auto step = [&](uint32_t k) {
        return closest_step<N, M>(nodes_.data(), blocks_.data(), slots[k], stacks[k], c);
    };
    auto finish = [&](const Slot& s) { out.set(s.index, s.hit); };
    run_stream(rays.count, slots, begin, step, finish);
    add_counts(counters, c.nodes, c.leaves, c.blocks);
}

template <std::size_t N, std::size_t M>
void TriangleBvhT<N, M>::occluded_stream(const RayStream& rays, uint8_t* occluded,
                                         BvhCounters* counters, StreamMode mode) const {
    using namespace bvh_detail;
    if (mode == StreamMode::SortedPackets) return occluded_sorted_packets(rays, occluded, counters);
    using Slot = StreamSlot<N, M>;
    Slot slots[kStreamSlots];
    uint32_t stacks[kStreamSlots][kStackSize];
    StreamCounts c;
    auto begin = [&](Slot& s, std::size_t i) {
        const Ray1 r = rays.ray(i);
        occluded[i] = 0;
        if (root_ == kBvhEmpty || unusable(r)) return false;
        s.start(r, root_, i);
        s.hit.id = kInvalidId;
        s.tcull = r.tmax;
        return true;
    };
    auto step = [&](uint32_t k) {
        return any_step<N, M>(nodes_.data(), blocks_.data(), slots[k], stacks[k], c);
    };
    auto finish = [&](const Slot& s) { occluded[s.index] = s.hit.id != kInvalidId; };
    run_stream(rays.count, slots, begin, step, finish);
    add_counts(counters, c.nodes, c.leaves, c.blocks);
}

namespace bvh_detail {

// Rays order[0 .. n) of a sorted stream as one packet (lanes past n repeat the last ray) with
// their tmax; returns the lanes to trace: those within n whose ray is usable.
inline uint32_t load_sorted_packet(const RayStream& rays, const uint32_t* order, std::size_t n,
                                   RayPacket& p, float* tmax) {
    uint32_t active = 0;
    for (std::size_t l = 0; l < kBlockWidth; ++l) {
        const Ray1 r = rays.ray(order[std::min(l, n - 1)]);
        p.ox[l] = r.ox, p.oy[l] = r.oy, p.oz[l] = r.oz;
        p.dx[l] = r.dx, p.dy[l] = r.dy, p.dz[l] = r.dz, p.tmin[l] = r.tmin;
        tmax[l] = r.tmax;
        active |= uint32_t(l < n && !unusable(r)) << l;
    }
    return active;
}

}  // namespace bvh_detail

// Sorted packets: W consecutive rays of the sorted order per packet. The packet kernels give
// every ray exactly its single-ray answer, including the rays that leave the packet.
template <std::size_t N, std::size_t M>
void TriangleBvhT<N, M>::intersect_sorted_packets(const RayStream& rays, const HitStream& out,
                                                  BvhCounters* counters) const {
    using namespace bvh_detail;
    if (root_ == kBvhEmpty) {
        for (std::size_t i = 0; i < rays.count; ++i) out.set(i, TriHit{});
        return;
    }
    const uint32_t* order = stream_order_of(rays);
    constexpr std::size_t W = kBlockWidth;
    for (std::size_t first = 0; first < rays.count; first += W) {
        const std::size_t n = std::min(W, rays.count - first);
        RayPacket p;
        PacketHits h;
        const uint32_t active = load_sorted_packet(rays, order + first, n, p, h.t);
        // As intersect(): an unusable ray keeps TriHit{}, a usable one starts at its tmax.
        for (std::size_t l = 0; l < W; ++l) {
            if (!((active >> l) & 1u)) h.t[l] = kInf;
            h.u[l] = h.v[l] = 0.f;
            h.id[l] = kInvalidId;
        }
        intersect_packet(p, active, h, counters);
        for (std::size_t l = 0; l < n; ++l)
            out.set(order[first + l], TriHit{h.t[l], h.u[l], h.v[l], h.id[l]});
    }
}

template <std::size_t N, std::size_t M>
void TriangleBvhT<N, M>::occluded_sorted_packets(const RayStream& rays, uint8_t* occluded,
                                                 BvhCounters* counters) const {
    using namespace bvh_detail;
    if (root_ == kBvhEmpty) {
        for (std::size_t i = 0; i < rays.count; ++i) occluded[i] = 0;
        return;
    }
    const uint32_t* order = stream_order_of(rays);
    constexpr std::size_t W = kBlockWidth;
    for (std::size_t first = 0; first < rays.count; first += W) {
        const std::size_t n = std::min(W, rays.count - first);
        RayPacket p;
        alignas(64) float tmax[W];
        const uint32_t active = load_sorted_packet(rays, order + first, n, p, tmax);
        const uint32_t blocked = occluded_packet(p, tmax, active, counters);
        for (std::size_t l = 0; l < n; ++l) occluded[order[first + l]] = (blocked >> l) & 1u;
    }
}

}  // namespace foton::kern
