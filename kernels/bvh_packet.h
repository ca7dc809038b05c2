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

// Below this many active rays a subtree is cheaper ray by ray than as a packet (a packet pays
// for all W lanes at every node and triangle).
inline constexpr int kPacketMinActive = kPacket >= 16 ? 4 : 2;

// The packet's rays for the per-ray box test of one child: the arithmetic of BoxRay::test, one
// ray per lane (all lanes share the octant, so the same near and far rows serve every ray).
struct LaneRays {
    PacketV ox, oy, oz, ix, iy, iz, fx, fy, fz, tmin;

    LaneRays(const RayPacket& p, uint32_t lanes) {
        alignas(64) float inv[3][kPacket], far[3][kPacket];
        const float* d[3] = {p.dx, p.dy, p.dz};
        for (int a = 0; a < 3; ++a)
            for (std::size_t i = 0; i < kPacket; ++i) {
                // Lanes outside the packet get a harmless finite factor; their results are masked.
                inv[a][i] = ((lanes >> i) & 1u) ? 1.f / d[a][i] : 1.f;
                far[a][i] = inv[a][i] * kBvhFarScale;
            }
        ox = PacketV::load_aligned(p.ox), oy = PacketV::load_aligned(p.oy);
        oz = PacketV::load_aligned(p.oz), tmin = PacketV::load_aligned(p.tmin);
        ix = PacketV::load_aligned(inv[0]), iy = PacketV::load_aligned(inv[1]);
        iz = PacketV::load_aligned(inv[2]), fx = PacketV::load_aligned(far[0]);
        fy = PacketV::load_aligned(far[1]), fz = PacketV::load_aligned(far[2]);
    }

    // Rays (bits) that enter child c of `node` before their own cull distance.
    template <std::size_t N>
    uint32_t test(const WideNode<N>& node, const BoxPacket<N>& bp, std::size_t c,
                  const PacketV& cull) const {
        const float* b = &node.bounds[0][0] + c;
        const PacketV tnx = (PacketV(b[bp.near[0]]) - ox) * ix;
        const PacketV tny = (PacketV(b[bp.near[1]]) - oy) * iy;
        const PacketV tnz = (PacketV(b[bp.near[2]]) - oz) * iz;
        const PacketV tfx = (PacketV(b[bp.far[0]]) - ox) * fx;
        const PacketV tfy = (PacketV(b[bp.far[1]]) - oy) * fy;
        const PacketV tfz = (PacketV(b[bp.far[2]]) - oz) * fz;
        const PacketV tn = simd::vmax(tnx, simd::vmax(tny, simd::vmax(tnz, tmin)));
        const PacketV tf = simd::vmin(tfx, simd::vmin(tfy, simd::vmin(tfz, cull)));
        return simd::movemask(tn <= tf);
    }
};

struct PacketEntry {
    uint32_t ref;
    float t;        // the packet's entry bound
    uint32_t rays;  // the rays that enter it
};

// Children of a node the packet enters: the interval test first (one test for all children),
// then the per-ray test of the survivors. Returns how many, near to far in `out`.
template <std::size_t N>
inline std::size_t packet_children(const WideNode<N>& node, const BoxPacket<N>& bp,
                                   const LaneRays& lr, const PacketV& cull, float cull_max,
                                   uint32_t rays, PacketEntry* out) {
    simd::FloatW<N> tnv;
    uint32_t mask = bp.test(node, cull_max, tnv);
    if (mask == 0) return 0;
    alignas(64) float tn[N];
    tnv.store_aligned(tn);
    std::size_t n = 0;
    for (; mask; mask &= mask - 1) {
        const uint32_t c = uint32_t(__builtin_ctz(mask));
        const uint32_t r = lr.test(node, bp, c, cull) & rays;
        if (r == 0) continue;
        // Insertion by entry bound, nearest last (it is popped first).
        std::size_t j = n++;
        for (; j > 0 && out[j - 1].t < tn[c]; --j) out[j] = out[j - 1];
        out[j] = {node.child[c], tn[c], r};
    }
    return n;
}

}  // namespace bvh_detail
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

    const BoxPacket<N> bp = make_box_packet<N>(p, lanes);
    const LaneRays lr(p, lanes);
    // The packet's hits live in h between leaves; the cull distances in registers.
    auto cull_of = [&](PacketV& cull) {
        alignas(64) float c[kPacket];
        float m = -kInf;
        for (std::size_t i = 0; i < kPacket; ++i) {
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
            const PacketV ox = lr.ox, oy = lr.oy, oz = lr.oz;
            const PacketV dx = PacketV::load_aligned(p.dx), dy = PacketV::load_aligned(p.dy),
                          dz = PacketV::load_aligned(p.dz);
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
                    const detail::TriV tri{
                        PacketV(blk.v0x[j]), PacketV(blk.v0y[j]), PacketV(blk.v0z[j]),
                        PacketV(blk.e1x[j]), PacketV(blk.e1y[j]), PacketV(blk.e1z[j]),
                        PacketV(blk.e2x[j]), PacketV(blk.e2y[j]), PacketV(blk.e2z[j])};
                    const detail::BlockTest bt =
                        detail::test(ox, oy, oz, dx, dy, dz, lr.tmin, PacketV(kInf), tri);
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
                        alignas(64) uint32_t ids[kPacket];
                        alignas(64) float us[kPacket], vs[kPacket], bu[kPacket], bv[kPacket];
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

    const BoxPacket<N> bp = make_box_packet<N>(p, lanes);
    const LaneRays lr(p, lanes);
    alignas(64) float tm[kPacket];
    for (std::size_t i = 0; i < kPacket; ++i) tm[i] = ((lanes >> i) & 1u) ? tmax[i] : -kInf;
    const PacketV cull = PacketV::load_aligned(tm);
    float cull_max = -kInf;
    for (uint32_t b = lanes; b; b &= b - 1) cull_max = std::max(cull_max, tm[__builtin_ctz(b)]);
    const PacketV dx = PacketV::load_aligned(p.dx), dy = PacketV::load_aligned(p.dy),
                  dz = PacketV::load_aligned(p.dz);

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
                    const detail::TriV tri{
                        PacketV(blk.v0x[j]), PacketV(blk.v0y[j]), PacketV(blk.v0z[j]),
                        PacketV(blk.e1x[j]), PacketV(blk.e1y[j]), PacketV(blk.e1z[j]),
                        PacketV(blk.e2x[j]), PacketV(blk.e2y[j]), PacketV(blk.e2z[j])};
                    const detail::BlockTest bt =
                        detail::test(lr.ox, lr.oy, lr.oz, dx, dy, dz, lr.tmin, cull, tri);
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
    if (counters) {
        counters->nodes += n_nodes;
        counters->leaves += n_leaves;
        counters->blocks += n_blocks;
    }
    return blocked;
}

}  // namespace foton::kern
