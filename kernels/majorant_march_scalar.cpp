// march_majorant's scalar twin: the reference the SIMD kernel is tested against, and the
// march of a single flight. Every step is written as the kernel computes it (each branch of
// the kernel's selects is an if here), so the two agree bit for bit.
#include "majorant_march.h"

namespace foton::kern {

namespace {

struct Flight {
    float t, tau, maj;
    bool collided;
};

Flight march_one(const MajorantGrid& g, const float o[3], const float d[3], float t_start,
                 float t_end, float tau) {
    Flight out{t_end, tau, 0.f, false};
    // The box's slab test clips [t_start, t_end].
    float inv[3], t0 = t_start, t1 = t_end;
    for (int a = 0; a < 3; ++a) {
        inv[a] = 1.f / d[a];
        const float hi = g.lo[a] + float(g.res[a]) * g.cell[a];
        float tn = (g.lo[a] - o[a]) * inv[a];
        float tf = (hi - o[a]) * inv[a];
        if (tn > tf) {
            const float s = tn;
            tn = tf;
            tf = s;
        }
        t0 = tn > t0 ? tn : t0;
        t1 = tf < t1 ? tf : t1;
    }
    if (!(t0 < t1)) return out;
    float c[3], step[3], next[3];
    for (int a = 0; a < 3; ++a) {
        float x = float(int((o[a] + t0 * d[a] - g.lo[a]) * g.inv_cell[a]));
        const float top = float(g.res[a] - 1);
        x = x < 0.f ? 0.f : x;
        x = x > top ? top : x;
        c[a] = x;
        step[a] = d[a] > 0.f ? 1.f : (d[a] < 0.f ? -1.f : 0.f);
        const float plane = step[a] > 0.f ? c[a] + 1.f : c[a];
        next[a] = step[a] == 0.f ? 3.4e38f : (g.lo[a] + plane * g.cell[a] - o[a]) * inv[a];
    }
    float t = t0;
    for (;;) {
        const bool x_first = next[0] < next[1];
        const float n01 = x_first ? next[0] : next[1];
        const bool z = next[2] < n01;
        const float boundary = z ? next[2] : n01;
        const float seg_end = boundary < t1 ? boundary : t1;
        const int cell = int((c[2] * float(g.res[1]) + c[1]) * float(g.res[0]) + c[0]);
        const float m = g.majorant[cell] * g.scale;
        const float need = m * (seg_end - t);
        if (m > 0.f && need >= out.tau) {
            out.t = t + out.tau / m;
            out.maj = m;
            out.collided = true;
            return out;
        }
        out.tau = out.tau - need;
        if (!(seg_end < t1)) return out;
        const int axis = z ? 2 : (x_first ? 0 : 1);
        c[axis] = c[axis] + step[axis];
        if (c[axis] < 0.f || c[axis] > float(g.res[axis] - 1)) return out;
        const float plane = step[axis] > 0.f ? c[axis] + 1.f : c[axis];
        next[axis] = (g.lo[axis] + plane * g.cell[axis] - o[axis]) * inv[axis];
        t = seg_end;
    }
}

}  // namespace

void march_majorant_scalar(const MajorantGrid& g, const MarchFlights& f, std::size_t count) {
    for (std::size_t i = 0; i < count; ++i) {
        const float o[3] = {f.ox[i], f.oy[i], f.oz[i]}, d[3] = {f.dx[i], f.dy[i], f.dz[i]};
        const Flight r = march_one(g, o, d, f.t[i], f.t_end[i], f.tau[i]);
        f.t[i] = r.t;
        f.majorant[i] = r.maj;
        f.collided[i] = r.collided ? 1 : 0;
    }
}

}  // namespace foton::kern
