#pragma once
// Packet traversal of TriangleBvhT (included by triangle_bvh.h): a packet of W rays (W = the
// widest SIMD width, 16 on AVX-512) walks the tree together, for coherent batches such as
// camera rays and shadow rays towards one point.
//
// Node test: interval arithmetic over the packet (after Boulos et al. 2007 and Wald et al.'s
// packet BVHs). Rays of one direction octant are bounded per axis by the box
// [min o, max o] x [min 1/d, max 1/d]; one N-wide slab test of those intervals gives, for all
// N children at once, a lower bound of every ray's entry distance and an upper bound of every
// ray's exit distance. A child none of the rays can enter is culled, so a node costs the packet
// about what it costs one ray. The bounds are computed with the same float operations as each
// ray's own test (bvh_traverse.h) at the interval ends, and rounding is monotonic, so a child
// any ray's own test would enter is never culled.
//
// Leaves: each triangle is tested against all W rays at once (one Möller–Trumbore evaluation
// per lane, the exact expressions of the single-ray kernel), keeping per ray the least (t, id).
// So every ray gets exactly the hit intersect() returns for it; the tests hold it to that.
//
// Rays the interval test cannot bound (a zero or non-finite direction component, another octant
// than the packet's first usable ray, NaN) are traced one by one with intersect() / occluded().
#include <cmath>
#include <cstring>

#include "bvh_traverse.h"  // StackEntry, kStackSize

namespace foton::kern {

namespace bvh_detail {

using PacketV = simd::FloatV;
using PacketMask = simd::MaskV;
inline constexpr std::size_t kPacket = simd::kWidth;

inline float bits_to_float(uint32_t b) {
    float f;
    std::memcpy(&f, &b, sizeof f);
    return f;
}

// The packet's interval bounds broadcast to the N lanes of a node test.
template <std::size_t N>
struct BoxPacket {
    using V = simd::FloatW<N>;
    V on[3], of[3];            // the origin bound that minimises entry / maximises exit, per axis
    V imin[3], imax[3];        // range of 1 / d (one sign per axis)
    V fmin[3], fmax[3];        // range of the far-plane factor 1 / d * kBvhFarScale
    V tmin;                    // least tmin
    uint32_t near[3], far[3];  // row offsets as in BoxRay

    // Lanes (children) some ray of the packet may enter before tcull; a lower bound of the
    // entry distance in `tn`. No NaN can arise: every factor is finite but the empty slots'
    // infinite planes, and those are never multiplied by zero.
    uint32_t test(const WideNode<N>& node, float tcull, V& tn) const {
        const float* b = &node.bounds[0][0];
        V lo = tmin, hi(tcull);
        for (int a = 0; a < 3; ++a) {
            const V n = V::load_aligned(b + near[a]) - on[a];
            const V f = V::load_aligned(b + far[a]) - of[a];
            lo = simd::vmax(lo, simd::vmin(n * imin[a], n * imax[a]));
            hi = simd::vmin(hi, simd::vmax(f * fmin[a], f * fmax[a]));
        }
        tn = lo;
        return simd::movemask(lo <= hi);
    }
};

// The octant of a ray the interval test can bound (bit a set when d_a < 0), or -1.
inline int packet_octant(const RayPacket& p, std::size_t i, float tmax) {
    const float d[3] = {p.dx[i], p.dy[i], p.dz[i]};
    const float o[3] = {p.ox[i], p.oy[i], p.oz[i]};
    if (!(p.tmin[i] < tmax) || std::isnan(p.tmin[i])) return -1;
    int oct = 0;
    for (int a = 0; a < 3; ++a) {
        const float inv = 1.f / d[a];
        if (!std::isfinite(o[a]) || !std::isfinite(inv) || d[a] == 0.f) return -1;
        oct |= int(d[a] < 0.f) << a;
    }
    return oct;
}

// Coherence, as the interval test needs it: lanes whose direction is within about 18 degrees of
// the packet's first usable ray go together, and only if their origins lie within 1/32 of the
// tree's diagonal of each other and at least a quarter of the lanes qualify. Wider packets
// (bounce rays, shadow rays from scattered points) bound so loosely that the packet would
// visit most of the tree, so those rays go alone.
inline constexpr float kPacketCosine = 0.95f;
inline constexpr float kPacketOriginSpan = 1.f / 32.f;
inline constexpr int kPacketMinLanes = int(kPacket / 4);

// Splits `active` into the lanes that traverse as a packet (returned: the octant and cone of
// the first usable lane) and the rest (`single`). Lanes with nothing to find (tmin >= tmax)
// are in neither: they have no hit.
inline uint32_t packet_lanes(const RayPacket& p, const float* tmax, uint32_t active, float max_span,
                             uint32_t& single) {
    uint32_t lanes = 0;
    single = 0;
    int octant = -1;
    float ax = 0.f, ay = 0.f, az = 0.f;  // the first lane's unit direction
    for (uint32_t b = active; b; b &= b - 1) {
        const uint32_t i = uint32_t(__builtin_ctz(b));
        if (!(p.tmin[i] < tmax[i])) continue;
        const int oct = packet_octant(p, i, tmax[i]);
        const float len = std::sqrt(p.dx[i] * p.dx[i] + p.dy[i] * p.dy[i] + p.dz[i] * p.dz[i]);
        if (oct >= 0 && octant < 0 && len > 0.f && std::isfinite(len)) {
            octant = oct;
            ax = p.dx[i] / len, ay = p.dy[i] / len, az = p.dz[i] / len;
        }
        if (oct >= 0 && oct == octant &&
            ax * p.dx[i] + ay * p.dy[i] + az * p.dz[i] >= kPacketCosine * len)
            lanes |= 1u << i;
        else
            single |= 1u << i;
    }
    if (__builtin_popcount(lanes) < kPacketMinLanes) {
        single |= lanes;
        return 0;
    }
    const float* o[3] = {p.ox, p.oy, p.oz};
    for (int a = 0; a < 3; ++a) {
        float lo = kInf, hi = -kInf;
        for (uint32_t b = lanes; b; b &= b - 1) {
            const float x = o[a][__builtin_ctz(b)];
            lo = std::min(lo, x), hi = std::max(hi, x);
        }
        if (!(hi - lo <= max_span)) {
            single |= lanes;
            return 0;
        }
    }
    return lanes;
}

template <std::size_t N>
BoxPacket<N> make_box_packet(const RayPacket& p, uint32_t lanes) {
    using V = simd::FloatW<N>;
    BoxPacket<N> bp;
    const float* o[3] = {p.ox, p.oy, p.oz};
    const float* d[3] = {p.dx, p.dy, p.dz};
    const uint32_t first = uint32_t(__builtin_ctz(lanes));
    float tmin = kInf;
    for (int a = 0; a < 3; ++a) {
        float omin = kInf, omax = -kInf, imin = kInf, imax = -kInf, fmin = kInf, fmax = -kInf;
        for (uint32_t b = lanes; b; b &= b - 1) {
            const uint32_t i = uint32_t(__builtin_ctz(b));
            const float inv = 1.f / d[a][i];
            const float f = inv * kBvhFarScale;
            omin = std::min(omin, o[a][i]);
            omax = std::max(omax, o[a][i]);
            imin = std::min(imin, inv);
            imax = std::max(imax, inv);
            fmin = std::min(fmin, f);
            fmax = std::max(fmax, f);
            if (a == 0) tmin = std::min(tmin, p.tmin[i]);
        }
        const bool neg = d[a][first] < 0.f;
        // Entry (b - o) / d is least at the largest origin for d > 0, at the smallest for d < 0;
        // exit the other way round.
        bp.on[a] = V(neg ? omin : omax);
        bp.of[a] = V(neg ? omax : omin);
        bp.imin[a] = V(imin), bp.imax[a] = V(imax);
        bp.fmin[a] = V(fmin), bp.fmax[a] = V(fmax);
        bp.near[a] = uint32_t((2 * a + neg) * N);
        bp.far[a] = uint32_t((2 * a + 1 - neg) * N);
    }
    bp.tmin = V(tmin);
    return bp;
}

// A float mask with lane i true where bit i of `bits` is set.
inline PacketMask packet_mask(uint32_t bits) {
    alignas(64) float f[kPacket];
    for (std::size_t i = 0; i < kPacket; ++i) f[i] = float((bits >> i) & 1u);
    return PacketV::load_aligned(f) != PacketV(0.f);
}

// The largest current bound of the packet's lanes in `lanes`: a box entered after it can hold
// no hit for any of them (the cull margin as in the single-ray traversal).
inline float packet_cull(const PacketV& t, const PacketMask& valid, uint32_t lanes) {
    alignas(64) float c[kPacket];
    xsimd::select(valid, t * PacketV(kBvhCullScale), t).store_aligned(c);
    float m = -kInf;
    for (uint32_t b = lanes; b; b &= b - 1) m = std::max(m, c[__builtin_ctz(b)]);
    return m;
}

}  // namespace bvh_detail

template <std::size_t N, std::size_t M>
void TriangleBvhT<N, M>::intersect_packet(const RayPacket& p, uint32_t active, PacketHits& h,
                                          BvhCounters* counters) const {
    using namespace bvh_detail;
    using V = simd::FloatW<N>;
    if (root_ == kBvhEmpty || active == 0) return;
    uint32_t single;
    const uint32_t lanes = packet_lanes(p, h.t, active, packet_span_, single);
    for (uint32_t b = single; b; b &= b - 1) {
        const uint32_t i = uint32_t(__builtin_ctz(b));
        TriHit th{h.t[i], h.u[i], h.v[i], h.id[i]};
        const Ray1 r{p.ox[i], p.oy[i], p.oz[i], p.dx[i], p.dy[i], p.dz[i], p.tmin[i], h.t[i]};
        if (intersect(r, th, counters))
            h.t[i] = th.t, h.u[i] = th.u, h.v[i] = th.v, h.id[i] = th.id;
    }
    if (lanes == 0) return;

    const BoxPacket<N> bp = make_box_packet<N>(p, lanes);
    const PacketV ox = PacketV::load_aligned(p.ox), oy = PacketV::load_aligned(p.oy),
                  oz = PacketV::load_aligned(p.oz), dx = PacketV::load_aligned(p.dx),
                  dy = PacketV::load_aligned(p.dy), dz = PacketV::load_aligned(p.dz),
                  tmin = PacketV::load_aligned(p.tmin);
    const PacketMask active_m = packet_mask(lanes);
    PacketV cur_t = PacketV::load_aligned(h.t), cur_u = PacketV::load_aligned(h.u),
            cur_v = PacketV::load_aligned(h.v);
    PacketV cur_id = PacketV::load_aligned(reinterpret_cast<const float*>(h.id));
    uint32_t valid_bits = 0;
    for (std::size_t i = 0; i < kPacket; ++i) valid_bits |= uint32_t(h.id[i] != kInvalidId) << i;
    PacketMask valid_m = packet_mask(valid_bits);
    float tcull = packet_cull(cur_t, valid_m, lanes);

    StackEntry stack[kStackSize];
    std::size_t sp = 0;
    uint32_t ref = root_;
    uint64_t n_nodes = 0, n_leaves = 0, n_blocks = 0;
    for (;;) {
        while (!bvh_is_leaf(ref)) {
            const Node& node = nodes_[ref];
            ++n_nodes;
            V tnv;
            uint32_t mask = bp.test(node, tcull, tnv);
            if (mask == 0) goto pop;
            alignas(64) float tn[N];
            tnv.store_aligned(tn);
            const uint32_t c0 = uint32_t(__builtin_ctz(mask));
            mask &= mask - 1;
            if (mask == 0) {
                ref = node.child[c0];
                continue;
            }
            // Push every hit child, sort far to near, enter the nearest.
            const std::size_t first = sp;
            stack[sp++] = {node.child[c0], tn[c0]};
            do {
                const uint32_t c = uint32_t(__builtin_ctz(mask));
                mask &= mask - 1;
                stack[sp++] = {node.child[c], tn[c]};
            } while (mask);
            for (std::size_t i = first + 1; i < sp; ++i) {
                const StackEntry e = stack[i];
                std::size_t j = i;
                for (; j > first && stack[j - 1].t < e.t; --j) stack[j] = stack[j - 1];
                stack[j] = e;
            }
            ref = stack[--sp].ref;
        }
        {
            ++n_leaves;
            const uint32_t nb = bvh_leaf_blocks(ref);
            n_blocks += nb;
            const Block* blocks = &blocks_[bvh_leaf_first(ref)];
            bool improved = false;
            for (uint32_t k = 0; k < nb; ++k) {
                const Block& blk = blocks[k];
                for (std::size_t j = 0; j < M; ++j) {
                    const uint32_t id = blk.id[j];
                    if (id == kInvalidId) break;  // unused lanes are at the end of a block
                    const detail::TriV tri{
                        PacketV(blk.v0x[j]), PacketV(blk.v0y[j]), PacketV(blk.v0z[j]),
                        PacketV(blk.e1x[j]), PacketV(blk.e1y[j]), PacketV(blk.e1z[j]),
                        PacketV(blk.e2x[j]), PacketV(blk.e2y[j]), PacketV(blk.e2z[j])};
                    const detail::BlockTest bt =
                        detail::test(ox, oy, oz, dx, dy, dz, tmin, PacketV(kInf), tri);
                    const PacketMask hit = bt.hit & active_m;
                    const PacketMask closer = hit & (bt.t < cur_t);
                    const uint32_t tie = simd::movemask(hit & (bt.t == cur_t) & valid_m);
                    if (simd::movemask(closer)) {
                        cur_t = xsimd::select(closer, bt.t, cur_t);
                        cur_u = xsimd::select(closer, bt.u, cur_u);
                        cur_v = xsimd::select(closer, bt.v, cur_v);
                        cur_id = xsimd::select(closer, PacketV(bits_to_float(id)), cur_id);
                        valid_m = valid_m | closer;
                        improved = true;
                    }
                    if (tie) {
                        // Same t as the current hit (a shared edge): the smaller id wins.
                        alignas(64) uint32_t ids[kPacket];
                        alignas(64) float us[kPacket], vs[kPacket], bu[kPacket], bv[kPacket];
                        cur_id.store_aligned(reinterpret_cast<float*>(ids));
                        cur_u.store_aligned(us), cur_v.store_aligned(vs);
                        bt.u.store_aligned(bu), bt.v.store_aligned(bv);
                        for (uint32_t b = tie; b; b &= b - 1) {
                            const uint32_t i = uint32_t(__builtin_ctz(b));
                            if (id < ids[i]) ids[i] = id, us[i] = bu[i], vs[i] = bv[i];
                        }
                        cur_id = PacketV::load_aligned(reinterpret_cast<const float*>(ids));
                        cur_u = PacketV::load_aligned(us), cur_v = PacketV::load_aligned(vs);
                    }
                }
            }
            if (improved) tcull = packet_cull(cur_t, valid_m, lanes);
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
    alignas(64) float ts[kPacket], us[kPacket], vs[kPacket];
    alignas(64) uint32_t ids[kPacket];
    cur_t.store_aligned(ts), cur_u.store_aligned(us), cur_v.store_aligned(vs);
    cur_id.store_aligned(reinterpret_cast<float*>(ids));
    for (uint32_t b = lanes; b; b &= b - 1) {
        const uint32_t i = uint32_t(__builtin_ctz(b));
        h.t[i] = ts[i], h.u[i] = us[i], h.v[i] = vs[i], h.id[i] = ids[i];
    }
    if (counters) {
        counters->nodes += n_nodes;
        counters->leaves += n_leaves;
        counters->blocks += n_blocks;
    }
}

template <std::size_t N, std::size_t M>
uint32_t TriangleBvhT<N, M>::occluded_packet(const RayPacket& p, const float* tmax, uint32_t active,
                                             BvhCounters* counters) const {
    using namespace bvh_detail;
    using V = simd::FloatW<N>;
    if (root_ == kBvhEmpty || active == 0) return 0;
    uint32_t single;
    uint32_t lanes = packet_lanes(p, tmax, active, packet_span_, single);
    uint32_t occluded_bits = 0;
    for (uint32_t b = single; b; b &= b - 1) {
        const uint32_t i = uint32_t(__builtin_ctz(b));
        const Ray1 r{p.ox[i], p.oy[i], p.oz[i], p.dx[i], p.dy[i], p.dz[i], p.tmin[i], tmax[i]};
        if (occluded(r, counters)) occluded_bits |= 1u << i;
    }
    if (lanes == 0) return occluded_bits;

    const BoxPacket<N> bp = make_box_packet<N>(p, lanes);
    const PacketV ox = PacketV::load_aligned(p.ox), oy = PacketV::load_aligned(p.oy),
                  oz = PacketV::load_aligned(p.oz), dx = PacketV::load_aligned(p.dx),
                  dy = PacketV::load_aligned(p.dy), dz = PacketV::load_aligned(p.dz),
                  tmin = PacketV::load_aligned(p.tmin);
    alignas(64) float tm[kPacket];
    for (std::size_t i = 0; i < kPacket; ++i) tm[i] = ((lanes >> i) & 1u) ? tmax[i] : -kInf;
    const PacketV tmaxv = PacketV::load_aligned(tm);
    float tcull = -kInf;
    for (uint32_t b = lanes; b; b &= b - 1) tcull = std::max(tcull, tm[__builtin_ctz(b)]);

    uint32_t stack[kStackSize];
    std::size_t sp = 0;
    uint32_t ref = root_;
    uint64_t n_nodes = 0, n_leaves = 0, n_blocks = 0;
    for (;;) {
        while (!bvh_is_leaf(ref)) {
            const Node& node = nodes_[ref];
            ++n_nodes;
            V tnv;
            uint32_t mask = bp.test(node, tcull, tnv);
            if (mask == 0) goto pop;
            ref = node.child[__builtin_ctz(mask)];
            for (mask &= mask - 1; mask; mask &= mask - 1)
                stack[sp++] = node.child[__builtin_ctz(mask)];
        }
        {
            ++n_leaves;
            const uint32_t nb = bvh_leaf_blocks(ref);
            n_blocks += nb;
            const Block* blocks = &blocks_[bvh_leaf_first(ref)];
            for (uint32_t k = 0; k < nb; ++k) {
                const Block& blk = blocks[k];
                for (std::size_t j = 0; j < M; ++j) {
                    if (blk.id[j] == kInvalidId) break;
                    const detail::TriV tri{
                        PacketV(blk.v0x[j]), PacketV(blk.v0y[j]), PacketV(blk.v0z[j]),
                        PacketV(blk.e1x[j]), PacketV(blk.e1y[j]), PacketV(blk.e1z[j]),
                        PacketV(blk.e2x[j]), PacketV(blk.e2y[j]), PacketV(blk.e2z[j])};
                    const detail::BlockTest bt =
                        detail::test(ox, oy, oz, dx, dy, dz, tmin, tmaxv, tri);
                    const uint32_t hit = simd::movemask(bt.hit) & lanes;
                    if (hit == 0) continue;
                    occluded_bits |= hit;
                    lanes &= ~hit;
                    if (lanes == 0) goto done;
                }
            }
            // Finished rays no longer widen the culling bound.
            tcull = -kInf;
            for (uint32_t b = lanes; b; b &= b - 1) tcull = std::max(tcull, tm[__builtin_ctz(b)]);
        }
    pop:
        if (sp == 0) break;
        ref = stack[--sp];
    }
done:
    if (counters) {
        counters->nodes += n_nodes;
        counters->leaves += n_leaves;
        counters->blocks += n_blocks;
    }
    return occluded_bits;
}

}  // namespace foton::kern
