#include "record_octree.h"

#include <algorithm>
#include <cmath>

namespace foton {

void RecordOctree::reset(const Bounds3& bounds) {
    nodes_.clear();
    nodes_.emplace_back();
    const Vec3 d = bounds.empty() ? Vec3{1.f, 1.f, 1.f} : bounds.diagonal();
    size_ = std::max({d.x, d.y, d.z, 1e-6f}) * 1.02f;
    const Vec3 c = bounds.empty() ? Vec3{0.f, 0.f, 0.f} : bounds.center();
    lo_ = c - Vec3{0.5f * size_, 0.5f * size_, 0.5f * size_};
}

void RecordOctree::cell(const Vec3& p, int depth, int& ix, int& iy, int& iz) const {
    const int n = 1 << depth;
    const float scale = float(n) / size_;
    auto index = [&](float v, float lo) {
        const float f = std::floor((v - lo) * scale);
        return int(std::clamp(f, 0.f, float(n - 1)));
    };
    ix = index(p.x, lo_.x);
    iy = index(p.y, lo_.y);
    iz = index(p.z, lo_.z);
}

void RecordOctree::insert(uint32_t index, const Vec3& c, float r) {
    // The deepest level whose node edge is at least the sphere's diameter.
    int depth = 0;
    while (depth < kMaxDepth && size_ / float(1 << (depth + 1)) >= 2.f * r) ++depth;
    // Cells at the finest level shifted down, exactly as the queries compute theirs.
    int x0, y0, z0, x1, y1, z1;
    cell(c - Vec3{r, r, r}, kMaxDepth, x0, y0, z0);
    cell(c + Vec3{r, r, r}, kMaxDepth, x1, y1, z1);
    const int down = kMaxDepth - depth;
    x0 >>= down;
    y0 >>= down;
    z0 >>= down;
    x1 >>= down;
    y1 >>= down;
    z1 >>= down;
    for (int z = z0; z <= z1; ++z)
        for (int y = y0; y <= y1; ++y)
            for (int x = x0; x <= x1; ++x) {
                int32_t node = 0;
                for (int d = 0; d < depth; ++d) {
                    const int shift = depth - d - 1;
                    const int child =
                        ((x >> shift) & 1) | (((y >> shift) & 1) << 1) | (((z >> shift) & 1) << 2);
                    int32_t next = nodes_[std::size_t(node)].child[std::size_t(child)];
                    if (next < 0) {
                        next = int32_t(nodes_.size());
                        nodes_[std::size_t(node)].child[std::size_t(child)] = next;
                        nodes_.emplace_back();  // may move the nodes: index again below
                    }
                    node = next;
                }
                nodes_[std::size_t(node)].items.push_back(index);
            }
}

}  // namespace foton
