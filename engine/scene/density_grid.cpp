#include "density_grid.h"

#include <algorithm>
#include <cmath>

namespace foton {

DensityGrid::DensityGrid(int nx, int ny, int nz, std::vector<float> values, const Bounds3& box)
    : SampledGrid<float>(nx, ny, nz, std::move(values), box) {
    const int n[3] = {nx, ny, nz};
    for (float v : this->values()) max_ = std::max(max_, v);
    const float lo[3] = {box.lo.x, box.lo.y, box.lo.z}, hi[3] = {box.hi.x, box.hi.y, box.hi.z};
    for (int a = 0; a < 3; ++a) {
        frame_.lo[a] = lo[a];
        frame_.hi[a] = hi[a];
        frame_.res[a] = std::clamp(n[a], 1, 16);
        frame_.cell[a] = (hi[a] - lo[a]) / float(frame_.res[a]);
        frame_.inv_cell[a] = float(frame_.res[a]) / (hi[a] - lo[a]);
    }
    majorant_.assign(frame_.num_cells(), 0.f);
    // A majorant cell spans [c, c + 1) / res of the box; the samples whose trilinear support
    // reaches into it are those with centre within one sample spacing of it.
    for (int z = 0; z < frame_.res[2]; ++z)
        for (int y = 0; y < frame_.res[1]; ++y)
            for (int x = 0; x < frame_.res[0]; ++x) {
                int s0[3], s1[3];
                const int c[3] = {x, y, z};
                for (int a = 0; a < 3; ++a) {
                    // Sample i sits at (i + 0.5) / n; the cell covers [c / res, (c + 1) / res].
                    const float u0 = float(c[a]) / float(frame_.res[a]);
                    const float u1 = float(c[a] + 1) / float(frame_.res[a]);
                    s0[a] = int(std::floor(u0 * float(n[a]) - 0.5f));
                    s1[a] = int(std::floor(u1 * float(n[a]) - 0.5f)) + 1;
                }
                float m = 0.f;
                for (int k = s0[2]; k <= s1[2]; ++k)
                    for (int j = s0[1]; j <= s1[1]; ++j)
                        for (int i = s0[0]; i <= s1[0]; ++i) m = std::max(m, sample(i, j, k));
                majorant_[frame_.index(x, y, z)] = m;
            }
}

}  // namespace foton
