#include "scene_outline.h"

#include <algorithm>
#include <cmath>

#include "scene.h"

namespace foton {

// The boxes of the cells of a kVoxels^3 grid over the scene's bounds that some object's box
// (a triangle's, for meshes) overlaps: a conservative outline of the geometry that a few
// hundred boxes describe, whatever the triangle count.
std::vector<Bounds3> scene_outline(const Scene& scene, int n, bool merged) {
    const Bounds3 all = scene.bounds();
    std::vector<Bounds3> boxes;
    if (all.empty()) return boxes;
    const Vec3 lo = all.lo, size = all.diagonal();
    std::vector<uint8_t> mark(std::size_t(n) * std::size_t(n) * std::size_t(n), 0);
    auto index = [&](float v, int axis) {
        const float extent = size[axis];
        if (!(extent > 0.f)) return 0;
        return std::clamp(int(std::floor((v - lo[axis]) / extent * float(n))), 0, n - 1);
    };
    auto mark_box = [&](const Bounds3& b) {
        const int x0 = index(b.lo.x, 0), x1 = index(b.hi.x, 0);
        const int y0 = index(b.lo.y, 1), y1 = index(b.hi.y, 1);
        const int z0 = index(b.lo.z, 2), z1 = index(b.hi.z, 2);
        for (int z = z0; z <= z1; ++z)
            for (int y = y0; y <= y1; ++y)
                for (int x = x0; x <= x1; ++x)
                    mark[(std::size_t(z) * std::size_t(n) + std::size_t(y)) * std::size_t(n) +
                         std::size_t(x)] = 1;
    };
    for (uint32_t g = 0; g < scene.objects.size(); ++g) {
        const Object& o = scene.objects[g];
        if (o.kind != ObjectKind::Mesh) {
            mark_box(scene.object_bounds(g));
            continue;
        }
        const TriangleMesh& m = scene.meshes[o.index];
        for (uint32_t tri = 0; tri < m.indices.size() / 3; ++tri) {
            Vec3 p[3];
            scene.world_corners(g, tri, p[0], p[1], p[2]);
            Bounds3 b;
            for (const Vec3& q : p) b.extend(q);
            mark_box(b);
        }
    }
    const Vec3 cell{size.x / float(n), size.y / float(n), size.z / float(n)};
    auto edge = [&](int k, int axis) {
        return k == n ? all.hi[axis] : lo[axis] + cell[axis] * float(k);
    };
    if (!merged) {
        for (int z = 0; z < n; ++z)
            for (int y = 0; y < n; ++y)
                for (int x = 0; x < n; ++x)
                    if (mark[(std::size_t(z) * std::size_t(n) + std::size_t(y)) * std::size_t(n) +
                             std::size_t(x)]) {
                        Bounds3 b;
                        b.lo = {edge(x, 0), edge(y, 1), edge(z, 2)};
                        b.hi = {edge(x + 1, 0), edge(y + 1, 1), edge(z + 1, 2)};
                        boxes.push_back(b);
                    }
        return boxes;
    }
    // Greedy merging into boxes (grow along x, then z, then y while every cell is occupied and
    // not yet taken): the same union in a few dozen boxes instead of thousands of voxels.
    auto at = [&](int x, int y, int z) -> uint8_t& {
        return mark[(std::size_t(z) * std::size_t(n) + std::size_t(y)) * std::size_t(n) +
                    std::size_t(x)];
    };
    auto full = [&](int x0, int x1, int y0, int y1, int z0, int z1) {
        for (int z = z0; z <= z1; ++z)
            for (int y = y0; y <= y1; ++y)
                for (int x = x0; x <= x1; ++x)
                    if (at(x, y, z) != 1) return false;
        return true;
    };
    for (int z = 0; z < n; ++z)
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) {
                if (at(x, y, z) != 1) continue;
                int x1 = x, z1 = z, y1 = y;
                while (x1 + 1 < n && at(x1 + 1, y, z) == 1) ++x1;
                while (z1 + 1 < n && full(x, x1, y, y, z1 + 1, z1 + 1)) ++z1;
                while (y1 + 1 < n && full(x, x1, y1 + 1, y1 + 1, z, z1)) ++y1;
                for (int zz = z; zz <= z1; ++zz)
                    for (int yy = y; yy <= y1; ++yy)
                        for (int xx = x; xx <= x1; ++xx) at(xx, yy, zz) = 2;  // taken
                Bounds3 b;
                b.lo = {edge(x, 0), edge(y, 1), edge(z, 2)};
                b.hi = {edge(x1 + 1, 0), edge(y1 + 1, 1), edge(z1 + 1, 2)};
                boxes.push_back(b);
            }
    return boxes;
}

}  // namespace foton
