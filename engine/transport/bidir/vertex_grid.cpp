#include "vertex_grid.h"

#include <cmath>

namespace foton {

void VertexGrid::build(const LightVertices& v, float radius, bool simd) {
    simd_ = simd;
    start_.clear();
    index_.clear();
    if (v.size() == 0) return;
    Bounds3 b;
    for (std::size_t i = 0; i < v.size(); ++i) b.extend(v.position(i));
    lo_ = b.lo;
    inv_cell_ = 1.f / (2.f * radius);
    r2_ = radius * radius;
    const std::size_t buckets = v.size();
    start_.assign(buckets + 1, 0);
    std::vector<uint32_t> cell(v.size());
    for (std::size_t i = 0; i < v.size(); ++i) {
        const int x = int(std::floor((v.px[i] - lo_.x) * inv_cell_));
        const int y = int(std::floor((v.py[i] - lo_.y) * inv_cell_));
        const int z = int(std::floor((v.pz[i] - lo_.z) * inv_cell_));
        cell[i] = bucket(x, y, z);
        ++start_[cell[i] + 1];
    }
    for (std::size_t k = 1; k <= buckets; ++k) start_[k] += start_[k - 1];
    index_.resize(v.size());
    std::vector<uint32_t> fill(start_.begin(), start_.end() - 1);
    for (std::size_t i = 0; i < v.size(); ++i) index_[fill[cell[i]]++] = uint32_t(i);
    const std::size_t padded = v.size() + simd::kWidth;
    x_.assign(padded, 0.f);
    y_.assign(padded, 0.f);
    z_.assign(padded, 0.f);
    for (std::size_t j = 0; j < v.size(); ++j) {
        x_[j] = v.px[index_[j]];
        y_[j] = v.py[index_[j]];
        z_[j] = v.pz[index_[j]];
    }
}

}  // namespace foton
