// Coherent grid traversal, after Wald, Ize, Kensler, Knoll and Parker (2006): a bundle of
// rays whose directions agree in sign along one dominant axis K walks the grid slice by slice
// along K. In each slice the bundle's footprint is the rectangle of cells spanned by all rays
// where they enter and leave the slice; every triangle of those cells is tested against all
// rays at once (W rays per SIMD test, kernel 1's packet shape). A mailbox keeps a triangle
// that spans several cells from being tested twice, and the walk stops once every ray has a
// hit that lies before the slice just finished. Bundles that do not share a direction sign
// fall back to single-ray traversal.
#include <algorithm>
#include <cmath>

#include "mailbox.h"
#include "uniform_grid.h"

namespace foton::kern {

namespace {

using simd::FloatV;
using simd::MaskV;

}  // namespace

void UniformGrid::intersect_packets(const RayPacket* pk, std::size_t np, PacketHits* hits,
                                    GridCounters* counters) const {
    if (empty() || np == 0) return;
    constexpr std::size_t W = kBlockWidth;
    np = std::min(np, kMaxGridPackets);

    // Active lanes (a non-empty [tmin, tmax] interval) and the dominant axis of the first one.
    MaskV active[kMaxGridPackets];
    int K = -1;
    for (std::size_t p = 0; p < np; ++p) {
        active[p] = FloatV::load_aligned(hits[p].t) > FloatV::load_aligned(pk[p].tmin);
        const uint32_t bits = simd::movemask(active[p]);
        if (K < 0 && bits) {
            const int l = __builtin_ctz(bits);
            const float ad[3] = {std::fabs(pk[p].dx[l]), std::fabs(pk[p].dy[l]),
                                 std::fabs(pk[p].dz[l])};
            K = ad[0] >= ad[1] ? (ad[0] >= ad[2] ? 0 : 2) : (ad[1] >= ad[2] ? 1 : 2);
        }
    }
    if (K < 0) return;
    const int U = (K + 1) % 3, V = (K + 2) % 3;
    auto dir = [&](std::size_t p, int a) -> const float* {
        return a == 0 ? pk[p].dx : a == 1 ? pk[p].dy : pk[p].dz;
    };
    auto org = [&](std::size_t p, int a) -> const float* {
        return a == 0 ? pk[p].ox : a == 1 ? pk[p].oy : pk[p].oz;
    };

    // Every active ray must head the same way along K.
    const uint32_t first = [&] {
        for (std::size_t p = 0; p < np; ++p)
            if (const uint32_t b = simd::movemask(active[p]))
                return uint32_t(p * W) + __builtin_ctz(b);
        return 0u;
    }();
    const float sK = dir(first / W, K)[first % W] > 0.f ? 1.f : -1.f;
    bool coherent = true;
    for (std::size_t p = 0; p < np && coherent; ++p) {
        const FloatV d = FloatV::load_aligned(dir(p, K)) * FloatV(sK);
        coherent = simd::movemask(active[p] & !(d > FloatV(0.f))) == 0;
    }
    if (!coherent) {
        for (std::size_t p = 0; p < np; ++p)
            for (uint32_t bits = simd::movemask(active[p]); bits; bits &= bits - 1) {
                const int l = __builtin_ctz(bits);
                const Ray1 r{pk[p].ox[l], pk[p].oy[l], pk[p].oz[l],   pk[p].dx[l],
                             pk[p].dy[l], pk[p].dz[l], pk[p].tmin[l], hits[p].t[l]};
                TriHit h;
                if (intersect(r, h, counters)) {
                    hits[p].t[l] = h.t;
                    hits[p].u[l] = h.u;
                    hits[p].v[l] = h.v;
                    hits[p].id[l] = h.id;
                }
            }
        return;
    }

    // Each ray's parameter interval inside the grid box, and the range of K slices.
    alignas(64) float t0[kMaxGridPackets][W], t1[kMaxGridPackets][W];
    alignas(64) float inv_dK[kMaxGridPackets][W];
    float k_enter = kInf, k_leave = -kInf;  // along +K after flipping by sK
    for (std::size_t p = 0; p < np; ++p) {
        FloatV lo = FloatV::load_aligned(pk[p].tmin), hi = FloatV::load_aligned(hits[p].t);
        for (int a = 0; a < 3; ++a) {
            const FloatV o = FloatV::load_aligned(org(p, a));
            const FloatV inv = FloatV(1.f) / FloatV::load_aligned(dir(p, a));
            const FloatV ta = (FloatV(frame_.lo[a]) - o) * inv;
            const FloatV tb = (FloatV(frame_.hi[a]) - o) * inv;
            // NaN (a parallel ray with its origin on a slab plane) leaves the interval as is.
            lo = xsimd::select(simd::vmin(ta, tb) > lo, simd::vmin(ta, tb), lo);
            hi = xsimd::select(simd::vmax(ta, tb) < hi, simd::vmax(ta, tb), hi);
            if (a == K) inv.store_aligned(inv_dK[p]);
        }
        active[p] = active[p] & (lo <= hi);
        lo.store_aligned(t0[p]);
        hi.store_aligned(t1[p]);
        const FloatV oK = FloatV::load_aligned(org(p, K)), dK = FloatV::load_aligned(dir(p, K));
        const FloatV enter = (oK + lo * dK) * FloatV(sK), leave = (oK + hi * dK) * FloatV(sK);
        k_enter = std::min(k_enter, simd::hmin(xsimd::select(active[p], enter, FloatV(kInf))));
        k_leave = std::max(k_leave, simd::hmax(xsimd::select(active[p], leave, FloatV(-kInf))));
    }
    if (!(k_enter <= k_leave)) return;
    const int step = sK > 0.f ? 1 : -1;
    const int k_first = frame_.cell_of(K, k_enter * sK), k_last = frame_.cell_of(K, k_leave * sK);

    // A packet whose rays are all finished takes no more tests: later triangles cannot beat
    // its hits. (Skipping it is safe with the mailbox for the same reason.)
    bool alive[kMaxGridPackets];
    for (std::size_t p = 0; p < np; ++p) alive[p] = simd::movemask(active[p]) != 0;
    Mailbox<9> mailbox;
    uint64_t cells = 0, tests = 0, skips = 0;
    const float epsU = 1e-5f * frame_.cell[U], epsV = 1e-5f * frame_.cell[V];
    int c[3];
    for (int k = k_first;; k += step) {
        const float plane_lo = frame_.lo[K] + float(k) * frame_.cell[K];
        const float plane_hi = frame_.lo[K] + float(k + 1) * frame_.cell[K];
        const float entry = step > 0 ? plane_lo : plane_hi, exit = step > 0 ? plane_hi : plane_lo;
        // The footprint of the bundle in this slice.
        float umin = kInf, umax = -kInf, vmin = kInf, vmax = -kInf;
        FloatV t_exit[kMaxGridPackets];
        for (std::size_t p = 0; p < np; ++p) {
            const FloatV oK = FloatV::load_aligned(org(p, K));
            const FloatV inv = FloatV::load_aligned(inv_dK[p]);
            const FloatV ta = simd::vmax(FloatV::load_aligned(t0[p]), (FloatV(entry) - oK) * inv);
            const FloatV tb = simd::vmin(FloatV::load_aligned(t1[p]), (FloatV(exit) - oK) * inv);
            t_exit[p] = tb;
            const MaskV in = active[p] & (ta <= tb);
            if (simd::movemask(in) == 0) continue;
            const FloatV oU = FloatV::load_aligned(org(p, U)), dU = FloatV::load_aligned(dir(p, U));
            const FloatV oV = FloatV::load_aligned(org(p, V)), dV = FloatV::load_aligned(dir(p, V));
            const FloatV ua = oU + ta * dU, ub = oU + tb * dU;
            const FloatV va = oV + ta * dV, vb = oV + tb * dV;
            umin = std::min(umin, simd::hmin(xsimd::select(in, simd::vmin(ua, ub), FloatV(kInf))));
            umax = std::max(umax, simd::hmax(xsimd::select(in, simd::vmax(ua, ub), FloatV(-kInf))));
            vmin = std::min(vmin, simd::hmin(xsimd::select(in, simd::vmin(va, vb), FloatV(kInf))));
            vmax = std::max(vmax, simd::hmax(xsimd::select(in, simd::vmax(va, vb), FloatV(-kInf))));
        }
        if (umin <= umax) {
            const int u0 = frame_.cell_of(U, umin - epsU), u1 = frame_.cell_of(U, umax + epsU);
            const int v0 = frame_.cell_of(V, vmin - epsV), v1 = frame_.cell_of(V, vmax + epsV);
            c[K] = k;
            for (int v = v0; v <= v1; ++v)
                for (int u = u0; u <= u1; ++u) {
                    c[U] = u;
                    c[V] = v;
                    ++cells;
                    const uint32_t cell = frame_.index(c[0], c[1], c[2]);
                    // A nested grid traverses the bundle itself, clipped to its own box.
                    if (const int32_t child = child_of(cell); child >= 0)
                        children_[child].intersect_packets(pk, np, hits, counters);
                    for (uint32_t b = cell_begin_[cell]; b < cell_begin_[cell + 1]; ++b) {
                        const TriangleBlock& blk = blocks_[b];
                        for (std::size_t lane = 0; lane < W && blk.id[lane] != kInvalidId; ++lane) {
                            if (mailbox.seen(blk.id[lane])) {
                                ++skips;
                                continue;
                            }
                            for (std::size_t p = 0; p < np; ++p)
                                if (alive[p]) {
                                    intersect_packet(pk[p], blk, lane, hits[p]);
                                    ++tests;
                                }
                        }
                    }
                }
        }
        // Done when every ray has left the grid or holds a hit before this slice's end.
        bool done = true;
        for (std::size_t p = 0; p < np; ++p) {
            if (!alive[p]) continue;
            const FloatV t = FloatV::load_aligned(hits[p].t);
            const MaskV finished =
                (!active[p]) | (t <= t_exit[p]) | (FloatV::load_aligned(t1[p]) <= t_exit[p]);
            alive[p] = !xsimd::all(finished);
            done = done && !alive[p];
        }
        if (done || k == k_last) break;
    }
    if (counters) {
        counters->cells += cells;
        counters->packet_tests += tests;
        counters->mailbox_skips += skips;
    }
}

}  // namespace foton::kern
