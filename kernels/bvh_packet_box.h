#pragma once
// The packet's geometry for bvh_packet.h: which rays of a packet may travel together, the
// interval bounds of those rays for one N-wide test of a node's children, and the per-ray test
// of one child. The reasoning (conservative bounds, exact per-ray answers) is in bvh_packet.h.
#include <algorithm>
#include <cmath>
#include <cstring>

#include "bvh_node.h"
#include "moller_trumbore.h"
#include "simd.h"

namespace foton::kern {

namespace bvh_detail {

using PacketV = simd::FloatV;
using PacketMask = simd::MaskV;
// K, the packet width (Embree's vocabulary: N children per node, M triangles per leaf block,
// K rays per packet): one SIMD register of rays.
inline constexpr std::size_t kPacketK = simd::kWidth;

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
inline constexpr int kPacketMinLanes = int(kPacketK / 4);

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

// The packet's rays one per lane: origins, directions, and 1 / d for the box tests (computed
// once per packet, for the interval bounds and the per-ray child test alike). The per-ray test
// is the arithmetic of BoxRay::test; all lanes share the octant, so the same near and far rows
// serve every ray.
struct LaneRays {
    alignas(64) float inv[3][kPacketK];  // 1 / d (1 in lanes outside the packet: masked anyway)
    alignas(64) float far[3][kPacketK];  // 1 / d * kBvhFarScale
    PacketV ox, oy, oz, dx, dy, dz, ix, iy, iz, fx, fy, fz, tmin;

    LaneRays(const RayPacket& p, uint32_t lanes) {
        const float* d[3] = {p.dx, p.dy, p.dz};
        for (int a = 0; a < 3; ++a)
            for (std::size_t i = 0; i < kPacketK; ++i) {
                inv[a][i] = ((lanes >> i) & 1u) ? 1.f / d[a][i] : 1.f;
                far[a][i] = inv[a][i] * kBvhFarScale;
            }
        ox = PacketV::load_aligned(p.ox), oy = PacketV::load_aligned(p.oy);
        oz = PacketV::load_aligned(p.oz), tmin = PacketV::load_aligned(p.tmin);
        dx = PacketV::load_aligned(p.dx), dy = PacketV::load_aligned(p.dy);
        dz = PacketV::load_aligned(p.dz);
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

template <std::size_t N>
BoxPacket<N> make_box_packet(const RayPacket& p, const LaneRays& lr, uint32_t lanes) {
    using V = simd::FloatW<N>;
    BoxPacket<N> bp;
    const float* o[3] = {p.ox, p.oy, p.oz};
    const uint32_t first = uint32_t(__builtin_ctz(lanes));
    float tmin = kInf;
    for (uint32_t b = lanes; b; b &= b - 1) tmin = std::min(tmin, p.tmin[__builtin_ctz(b)]);
    for (int a = 0; a < 3; ++a) {
        float omin = kInf, omax = -kInf, imin = kInf, imax = -kInf, fmin = kInf, fmax = -kInf;
        for (uint32_t b = lanes; b; b &= b - 1) {
            const uint32_t i = uint32_t(__builtin_ctz(b));
            omin = std::min(omin, o[a][i]), omax = std::max(omax, o[a][i]);
            imin = std::min(imin, lr.inv[a][i]), imax = std::max(imax, lr.inv[a][i]);
            fmin = std::min(fmin, lr.far[a][i]), fmax = std::max(fmax, lr.far[a][i]);
        }
        const bool neg = lr.inv[a][first] < 0.f;
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
    alignas(64) float f[kPacketK];
    for (std::size_t i = 0; i < kPacketK; ++i) f[i] = float((bits >> i) & 1u);
    return PacketV::load_aligned(f) != PacketV(0.f);
}

// Below this many active rays a subtree is cheaper ray by ray than as a packet (a packet pays
// for all W lanes at every node and triangle).
inline constexpr int kPacketMinActive = kPacketK >= 16 ? 4 : 2;

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

}  // namespace foton::kern
