#pragma once
// 3D DDA over a uniform grid (Amanatides & Woo): visits the cells a ray crosses, front to
// back, handing each to a visitor together with the ray parameter at which the ray leaves
// that cell. Shared by the triangle grid of this directory and the engine's object grid.
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "ray1.h"

namespace foton::kern {

struct GridFrame {
    float lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
    int res[3] = {1, 1, 1};
    float cell[3] = {1, 1, 1}, inv_cell[3] = {1, 1, 1};

    // Fits a grid of about `target_cells` cells to the box [lo, hi], cells roughly cubic.
    static GridFrame fit(const float lo[3], const float hi[3], double target_cells, int max_res);
    uint32_t num_cells() const { return uint32_t(res[0]) * uint32_t(res[1]) * uint32_t(res[2]); }
    uint32_t index(int x, int y, int z) const {
        return (uint32_t(z) * uint32_t(res[1]) + uint32_t(y)) * uint32_t(res[0]) + uint32_t(x);
    }
    int cell_of(int axis, float x) const {
        const int c = int((x - lo[axis]) * inv_cell[axis]);
        return std::clamp(c, 0, res[axis] - 1);
    }
};

inline GridFrame GridFrame::fit(const float lo_in[3], const float hi_in[3], double target_cells,
                                int max_res) {
    GridFrame g;
    float ext[3];
    float diag2 = 0.f;
    for (int a = 0; a < 3; ++a) diag2 += (hi_in[a] - lo_in[a]) * (hi_in[a] - lo_in[a]);
    // Pad so that flat geometry (a single quad) still has a non-empty box and so that
    // triangles lying exactly on the boundary are inside.
    const float pad = 1e-5f * std::sqrt(diag2) + 1e-30f;
    for (int a = 0; a < 3; ++a) {
        g.lo[a] = lo_in[a] - pad;
        g.hi[a] = hi_in[a] + pad;
        ext[a] = g.hi[a] - g.lo[a];
    }
    const double maxext = std::max({ext[0], ext[1], ext[2]});
    // Cell edge so that volume / edge^3 = target, ignoring axes much thinner than a cell.
    double vol = 1.0;
    for (int a = 0; a < 3; ++a) vol *= std::max<double>(ext[a], maxext * 1e-3);
    const double edge = std::cbrt(vol / std::max(1.0, target_cells));
    for (int a = 0; a < 3; ++a) {
        g.res[a] = std::clamp(int(std::ceil(ext[a] / edge)), 1, max_res);
        g.cell[a] = ext[a] / float(g.res[a]);
        g.inv_cell[a] = float(g.res[a]) / ext[a];
    }
    return g;
}

// Walks the cells of `g` along `r` in order. `visit(cell, t_exit)` returns true to stop.
// `t_limit` is read before each step: the walk ends once the next cell starts beyond it
// (the caller lowers it as closer hits are found).
template <class Visit>
inline void dda_walk(const GridFrame& g, const Ray1& r, const float& t_limit, Visit&& visit) {
    const float o[3] = {r.ox, r.oy, r.oz};
    const float d[3] = {r.dx, r.dy, r.dz};
    float inv[3];
    float t0 = r.tmin, t1 = r.tmax;
    for (int a = 0; a < 3; ++a) {
        inv[a] = 1.f / d[a];
        float tn = (g.lo[a] - o[a]) * inv[a];
        float tf = (g.hi[a] - o[a]) * inv[a];
        if (tn > tf) std::swap(tn, tf);
        // NaN (origin on the slab plane of a parallel ray) leaves the interval unchanged.
        if (tn > t0) t0 = tn;
        if (tf < t1) t1 = tf;
    }
    if (!(t0 <= t1)) return;

    int c[3], step[3], out[3];
    float next[3];
    for (int a = 0; a < 3; ++a) {
        c[a] = g.cell_of(a, o[a] + t0 * d[a]);
        if (d[a] > 0.f) {
            step[a] = 1;
            out[a] = g.res[a];
        } else if (d[a] < 0.f) {
            step[a] = -1;
            out[a] = -1;
        } else {
            step[a] = 0;
            out[a] = -2;
        }
    }
    auto boundary = [&](int a) {
        if (step[a] == 0) return kInf;
        const int plane = step[a] > 0 ? c[a] + 1 : c[a];
        return (g.lo[a] + float(plane) * g.cell[a] - o[a]) * inv[a];
    };
    for (int a = 0; a < 3; ++a) next[a] = boundary(a);

    for (;;) {
        int axis = next[0] < next[1] ? 0 : 1;
        if (next[2] < next[axis]) axis = 2;
        const float t_exit = std::min(next[axis], t1);
        if (visit(g.index(c[0], c[1], c[2]), t_exit)) return;
        if (next[axis] > t1 || next[axis] > t_limit) return;
        c[axis] += step[axis];
        if (c[axis] == out[axis]) return;
        next[axis] = boundary(axis);
    }
}

}  // namespace foton::kern
