// march_majorant: W flights through the majorant grid at once, each lane at its own cell. A
// round computes, for every live lane, its cell's segment, whether tau runs out in it, and the
// step to the next cell; lanes that collided, reached t_end or left the grid stay masked until
// the last lane is done. The operations are majorant_march_scalar.cpp's, in its order, each of
// its branches computed for all lanes and selected.
#include <algorithm>

#include "majorant_march.h"
#include "simd.h"

namespace foton::kern {

namespace {

using simd::FloatV;
using simd::MaskV;
using IntV = xsimd::batch<int32_t, simd::Arch>;
constexpr std::size_t W = simd::kWidth;

}  // namespace

void march_majorant(const MajorantGrid& g, const MarchFlights& f, std::size_t count) {
    const FloatV zero(0.f), one(1.f), big(3.4e38f);
    alignas(64) float in[8][W];
    alignas(64) float out_t[W], out_m[W], out_c[W];
    for (std::size_t base = 0; base < count; base += W) {
        const std::size_t n = std::min(W, count - base);
        // The lanes' inputs, the tail padded with empty flights (t_end 0: done at once).
        const float* src[8] = {f.ox, f.oy, f.oz, f.dx, f.dy, f.dz, f.t, f.t_end};
        for (int k = 0; k < 8; ++k) {
            std::copy(src[k] + base, src[k] + base + n, in[k]);
            std::fill(in[k] + n, in[k] + W, k == 5 ? 1.f : 0.f);
        }
        alignas(64) float tau_in[W];
        std::copy(f.tau + base, f.tau + base + n, tau_in);
        std::fill(tau_in + n, tau_in + W, 1.f);
        const FloatV o[3] = {FloatV::load_aligned(in[0]), FloatV::load_aligned(in[1]),
                             FloatV::load_aligned(in[2])};
        const FloatV d[3] = {FloatV::load_aligned(in[3]), FloatV::load_aligned(in[4]),
                             FloatV::load_aligned(in[5])};
        const FloatV t_start = FloatV::load_aligned(in[6]), t_end = FloatV::load_aligned(in[7]);
        FloatV tau = FloatV::load_aligned(tau_in);
        FloatV inv[3], t0 = t_start, t1 = t_end;
        for (int a = 0; a < 3; ++a) {
            inv[a] = one / d[a];
            const FloatV lo(g.lo[a]), hi(g.lo[a] + float(g.res[a]) * g.cell[a]);
            const FloatV a0 = (lo - o[a]) * inv[a], a1 = (hi - o[a]) * inv[a];
            const MaskV swap = a0 > a1;
            const FloatV tn = xsimd::select(swap, a1, a0), tf = xsimd::select(swap, a0, a1);
            t0 = xsimd::select(tn > t0, tn, t0);
            t1 = xsimd::select(tf < t1, tf, t1);
        }
        MaskV live = t0 < t1;
        FloatV res_t = t_end, res_m = zero;
        MaskV res_c(false);
        FloatV c[3], step[3], next[3];
        for (int a = 0; a < 3; ++a) {
            // Dead lanes compute on a point inside the grid, so every gather stays in range.
            const FloatV p = xsimd::select(live, o[a] + t0 * d[a], FloatV(g.lo[a]));
            FloatV x = simd::to_float(simd::to_int((p - FloatV(g.lo[a])) * FloatV(g.inv_cell[a])));
            const FloatV top(float(g.res[a] - 1));
            x = xsimd::select(x < zero, zero, x);
            x = xsimd::select(x > top, top, x);
            c[a] = x;
            step[a] = xsimd::select(d[a] > zero, one, xsimd::select(d[a] < zero, -one, zero));
            const FloatV plane = xsimd::select(step[a] > zero, c[a] + one, c[a]);
            next[a] = xsimd::select(step[a] == zero, big,
                                    (FloatV(g.lo[a]) + plane * FloatV(g.cell[a]) - o[a]) * inv[a]);
        }
        FloatV t = t0;
        const FloatV res0(float(g.res[0])), res1(float(g.res[1]));
        while (xsimd::any(live)) {
            const MaskV x_first = next[0] < next[1];
            const FloatV n01 = xsimd::select(x_first, next[0], next[1]);
            const MaskV z = next[2] < n01;
            const FloatV boundary = xsimd::select(z, next[2], n01);
            const FloatV seg_end = xsimd::select(boundary < t1, boundary, t1);
            const IntV cell = simd::to_int((c[2] * res1 + c[1]) * res0 + c[0]);
            const FloatV m = simd::gather(g.majorant, cell) * FloatV(g.scale);
            const FloatV need = m * (seg_end - t);
            const MaskV hit = live & (m > zero) & (need >= tau);
            res_t = xsimd::select(hit, t + tau / m, res_t);
            res_m = xsimd::select(hit, m, res_m);
            res_c = res_c | hit;
            live = live & !hit;
            tau = xsimd::select(live, tau - need, tau);
            live = live & (seg_end < t1);
            // The step to the next cell, on the axis whose boundary comes first.
            const MaskV not_z = !z;
            const MaskV ax[3] = {not_z & x_first, not_z & (!x_first), z};
            MaskV out(false);
            for (int a = 0; a < 3; ++a) {
                const MaskV mv = live & ax[a];
                c[a] = xsimd::select(mv, c[a] + step[a], c[a]);
                out = out | (mv & ((c[a] < zero) | (c[a] > FloatV(float(g.res[a] - 1)))));
            }
            live = live & !out;
            for (int a = 0; a < 3; ++a) {
                const MaskV mv = live & ax[a];
                const FloatV plane = xsimd::select(step[a] > zero, c[a] + one, c[a]);
                next[a] = xsimd::select(
                    mv, (FloatV(g.lo[a]) + plane * FloatV(g.cell[a]) - o[a]) * inv[a], next[a]);
                // Lanes that left keep a cell inside the grid for the next round's gather.
                c[a] = xsimd::select(out & ax[a], c[a] - step[a], c[a]);
            }
            t = xsimd::select(live, seg_end, t);
        }
        res_t.store_aligned(out_t);
        res_m.store_aligned(out_m);
        xsimd::select(res_c, one, zero).store_aligned(out_c);
        for (std::size_t i = 0; i < n; ++i) {
            f.t[base + i] = out_t[i];
            f.majorant[base + i] = out_m[i];
            f.collided[base + i] = out_c[i] != 0.f ? 1 : 0;
        }
    }
}

}  // namespace foton::kern
