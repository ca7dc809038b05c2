#pragma once
// Packet traversal of TriangleBvhT (included by triangle_bvh.h): a packet of W rays (W = the
// widest SIMD width, 16 on AVX-512) walks the tree together, for coherent batches such as
// camera rays.
//
// Node test, in two steps (bvh_packet_box.h). First interval arithmetic over the packet (after
// Boulos et al. 2007 and Wald et al.'s packet BVHs): rays of one direction octant are bounded
// per axis by the box [min o, max o] x [min 1/d, max 1/d]; one N-wide slab test of those
// intervals bounds every ray's entry and exit for all N children at once, so a child none of
// the rays can enter costs one test for the whole packet. The bounds use the same float
// operations as each ray's own test (bvh_traverse.h) at the interval ends, and rounding is
// monotonic, so a child any ray's own test would enter is never culled. Then each surviving
// child is tested ray by ray (one ray per lane), which gives the rays that enter it.
//
// Leaves: each triangle is tested against the rays that entered the leaf, all lanes at once
// (the exact Möller–Trumbore expressions of the single-ray kernel), keeping per ray the least
// (t, id). A subtree that fewer than kPacketMinActive rays reach is finished ray by ray from
// there (closest_from / any_from), and rays that do not fit the packet (another octant, outside
// its cone, unusable) go ray by ray from the root. So every ray gets exactly the hit
// intersect() returns for it; the tests hold it to that.
#include "bvh_packet_box.h"
#include "bvh_traverse.h"  // StackEntry, kStackSize

namespace foton::kern {

template <std::size_t N, std::size_t M>
void TriangleBvhT<N, M>::intersect_packet(const RayPacket& p, uint32_t active, PacketHits& h,
                                          BvhCounters* counters) const {
    using namespace bvh_detail;
    if (root_ == kBvhEmpty || active == 0) return;
    uint32_t single;
    const uint32_t lanes = packet_lanes(p, h.t, active, packet_span_, single);
    // Rays handed to the single-ray traversal at subtree `ref` (their current hits as bounds).
    auto alone = [&](uint32_t ref, uint32_t rays) {
        for (uint32_t b = rays; b; b &= b - 1) {
            const uint32_t i = uint32_t(__builtin_ctz(b));
            TriHit th{h.t[i], h.u[i], h.v[i], h.id[i]};
            const Ray1 r{p.ox[i], p.oy[i], p.oz[i], p.dx[i], p.dy[i], p.dz[i], p.tmin[i], h.t[i]};
            if (closest_from(ref, r, th, counters))
                h.t[i] = th.t, h.u[i] = th.u, h.v[i] = th.v, h.id[i] = th.id;
        }
    };
    for (uint32_t b = single; b; b &= b - 1) {
        const uint32_t i = uint32_t(__builtin_ctz(b));
        if (!unusable({p.ox[i], p.oy[i], p.oz[i], p.dx[i], p.dy[i], p.dz[i], p.tmin[i], h.t[i]}))
            alone(root_, 1u << i);
    }
    if (lanes == 0) return;

    const LaneRays lr(p, lanes);
    const BoxPacket<N> bp = make_box_packet<N>(p, lr, lanes);
    // The packet's hits live in h between leaves; the cull distances in registers.
    auto cull_of = [&](PacketV& cull) {
        alignas(64) float c[kPacketK];
        float m = -kInf;
        for (std::size_t i = 0; i < kPacketK; ++i) {
            c[i] = h.id[i] != kInvalidId ? h.t[i] * kBvhCullScale : h.t[i];
            if ((lanes >> i) & 1u) m = std::max(m, c[i]);
        }
        cull = PacketV::load_aligned(c);
        return m;
    };
    PacketV cull;
    float cull_max = cull_of(cull);

    PacketEntry stack[kStackSize];
    std::size_t sp = 0;
    uint32_t ref = root_, rays = lanes;
    uint64_t n_nodes = 0, n_leaves = 0, n_blocks = 0;
    for (;;) {
        if (__builtin_popcount(rays) < kPacketMinActive) {
            alone(ref, rays);
            cull_max = cull_of(cull);
            goto pop;
        }
        if (!bvh_is_leaf(ref)) {
            ++n_nodes;
            PacketEntry kids[N];
            const std::size_t n = packet_children(nodes_[ref], bp, lr, cull, cull_max, rays, kids);
            if (n == 0) goto pop;
            for (std::size_t k = 0; k + 1 < n; ++k) stack[sp++] = kids[k];
            ref = kids[n - 1].ref, rays = kids[n - 1].rays;
            continue;
        }
        {
            ++n_leaves;
            const uint32_t nb = bvh_leaf_blocks(ref);
            n_blocks += nb;
            const Block* blocks = &blocks_[bvh_leaf_first(ref)];
            const PacketMask on = packet_mask(rays);
            PacketV cur_t = PacketV::load_aligned(h.t), cur_u = PacketV::load_aligned(h.u),
                    cur_v = PacketV::load_aligned(h.v),
                    cur_id = PacketV::load_aligned(reinterpret_cast<const float*>(h.id));
            bool improved = false;
            for (uint32_t k = 0; k < nb; ++k) {
                const Block& blk = blocks[k];
                for (std::size_t j = 0; j < M; ++j) {
                    const uint32_t id = blk.id[j];
                    if (id == kInvalidId) break;  // unused lanes are at the end of a block
                    const detail::TriV tri = detail::broadcast_lane<PacketV>(blk, j);
                    const detail::BlockTest bt = detail::test(lr.ox, lr.oy, lr.oz, lr.dx, lr.dy,
                                                              lr.dz, lr.tmin, PacketV(kInf), tri);
                    const PacketMask hit = bt.hit & on;
                    const PacketMask closer = hit & (bt.t < cur_t);
                    // Same t as a current hit (a shared edge): the smaller id wins.
                    uint32_t tie = simd::movemask(hit & (bt.t == cur_t));
                    if (simd::movemask(closer)) {
                        cur_t = xsimd::select(closer, bt.t, cur_t);
                        cur_u = xsimd::select(closer, bt.u, cur_u);
                        cur_v = xsimd::select(closer, bt.v, cur_v);
                        cur_id = xsimd::select(closer, PacketV(bits_to_float(id)), cur_id);
                        improved = true;
                    }
                    if (tie) {
                        alignas(64) uint32_t ids[kPacketK];
                        alignas(64) float us[kPacketK], vs[kPacketK], bu[kPacketK], bv[kPacketK];
                        cur_id.store_aligned(reinterpret_cast<float*>(ids));
                        cur_u.store_aligned(us), cur_v.store_aligned(vs);
                        bt.u.store_aligned(bu), bt.v.store_aligned(bv);
                        for (; tie; tie &= tie - 1) {
                            const uint32_t i = uint32_t(__builtin_ctz(tie));
                            // An invalid current id is tmax itself: a hit there is no hit.
                            if (ids[i] != kInvalidId && id < ids[i])
                                ids[i] = id, us[i] = bu[i], vs[i] = bv[i];
                        }
                        cur_id = PacketV::load_aligned(reinterpret_cast<const float*>(ids));
                        cur_u = PacketV::load_aligned(us), cur_v = PacketV::load_aligned(vs);
                    }
                }
            }
            cur_t.store_aligned(h.t), cur_u.store_aligned(h.u), cur_v.store_aligned(h.v);
            cur_id.store_aligned(reinterpret_cast<float*>(h.id));
            if (improved) cull_max = cull_of(cull);
        }
    pop:
        for (;;) {
            if (sp == 0) goto done;
            const PacketEntry& e = stack[--sp];
            if (e.t <= cull_max) {
                ref = e.ref, rays = e.rays;
                break;
            }
        }
    }
done:
    add_counts(counters, n_nodes, n_leaves, n_blocks);
}

template <std::size_t N, std::size_t M>
uint32_t TriangleBvhT<N, M>::occluded_packet(const RayPacket& p, const float* tmax, uint32_t active,
                                             BvhCounters* counters) const {
    using namespace bvh_detail;
    if (root_ == kBvhEmpty || active == 0) return 0;
    uint32_t single;
    uint32_t lanes = packet_lanes(p, tmax, active, packet_span_, single);
    uint32_t blocked = 0;
    auto alone = [&](uint32_t ref, uint32_t rays) {
        for (uint32_t b = rays; b; b &= b - 1) {
            const uint32_t i = uint32_t(__builtin_ctz(b));
            const Ray1 r{p.ox[i], p.oy[i], p.oz[i], p.dx[i], p.dy[i], p.dz[i], p.tmin[i], tmax[i]};
            if (any_from(ref, r, counters)) blocked |= 1u << i;
        }
    };
    for (uint32_t b = single; b; b &= b - 1) {
        const uint32_t i = uint32_t(__builtin_ctz(b));
        if (!unusable({p.ox[i], p.oy[i], p.oz[i], p.dx[i], p.dy[i], p.dz[i], p.tmin[i], tmax[i]}))
            alone(root_, 1u << i);
    }
    if (lanes == 0) return blocked;

    const LaneRays lr(p, lanes);
    const BoxPacket<N> bp = make_box_packet<N>(p, lr, lanes);
    alignas(64) float tm[kPacketK];
    for (std::size_t i = 0; i < kPacketK; ++i) tm[i] = ((lanes >> i) & 1u) ? tmax[i] : -kInf;
    const PacketV cull = PacketV::load_aligned(tm);
    float cull_max = -kInf;
    for (uint32_t b = lanes; b; b &= b - 1) cull_max = std::max(cull_max, tm[__builtin_ctz(b)]);

    PacketEntry stack[kStackSize];
    std::size_t sp = 0;
    uint32_t ref = root_, rays = lanes;
    uint64_t n_nodes = 0, n_leaves = 0, n_blocks = 0;
    for (;;) {
        rays &= ~blocked;  // rays already blocked elsewhere need nothing more
        if (rays == 0) goto pop;
        if (__builtin_popcount(rays) < kPacketMinActive) {
            alone(ref, rays);
            goto pop;
        }
        if (!bvh_is_leaf(ref)) {
            ++n_nodes;
            PacketEntry kids[N];
            const std::size_t n = packet_children(nodes_[ref], bp, lr, cull, cull_max, rays, kids);
            if (n == 0) goto pop;
            for (std::size_t k = 0; k + 1 < n; ++k) stack[sp++] = kids[k];
            ref = kids[n - 1].ref, rays = kids[n - 1].rays;
            continue;
        }
        {
            ++n_leaves;
            const uint32_t nb = bvh_leaf_blocks(ref);
            n_blocks += nb;
            const Block* blocks = &blocks_[bvh_leaf_first(ref)];
            for (uint32_t k = 0; k < nb && rays; ++k) {
                const Block& blk = blocks[k];
                for (std::size_t j = 0; j < M; ++j) {
                    if (blk.id[j] == kInvalidId) break;
                    const detail::TriV tri = detail::broadcast_lane<PacketV>(blk, j);
                    const detail::BlockTest bt =
                        detail::test(lr.ox, lr.oy, lr.oz, lr.dx, lr.dy, lr.dz, lr.tmin, cull, tri);
                    const uint32_t hit = simd::movemask(bt.hit) & rays;
                    if (hit == 0) continue;
                    blocked |= hit;
                    rays &= ~hit;
                    if ((blocked & lanes) == lanes) goto done;
                    if (rays == 0) break;
                }
            }
        }
    pop:
        if (sp == 0) break;
        ref = stack[--sp].ref;
        rays = stack[sp].rays;
    }
done:
    add_counts(counters, n_nodes, n_leaves, n_blocks);
    return blocked;
}

}  // namespace foton::kern
