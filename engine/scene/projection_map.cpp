#include "projection_map.h"

#include <algorithm>
#include <cmath>

#include "scene.h"

namespace foton {

void ProjectionMap::build(const Scene& scene, const Vec3& s, const Vec3& t, const Vec3& center,
                          float radius, int res) {
    res_ = res;
    radius_ = radius;
    cell_ = 2.f * radius / float(res);
    kept_.clear();
    std::vector<uint8_t> mark(std::size_t(res) * std::size_t(res), 0);
    // Marks the cells under the projected box of points, grown by a margin for rounding.
    const float margin = 1e-4f * radius;
    auto cell = [&](float v) {
        return std::clamp(int(std::floor((v + radius_) / cell_)), 0, res_ - 1);
    };
    auto mark_box = [&](float x0, float x1, float y0, float y1) {
        const int i0 = cell(x0 - margin), i1 = cell(x1 + margin);
        const int j0 = cell(y0 - margin), j1 = cell(y1 + margin);
        for (int j = j0; j <= j1; ++j)
            for (int i = i0; i <= i1; ++i) mark[std::size_t(j) * std::size_t(res_) + i] = 1;
    };
    // Marks the cells a projected triangle overlaps: those of its box that no edge's line
    // separates from it (the separating axis test in 2D, each cell grown by the margin).
    auto mark_triangle = [&](Point2 a, Point2 b, Point2 c) {
        const float x0 = std::min({a.x, b.x, c.x}), x1 = std::max({a.x, b.x, c.x});
        const float y0 = std::min({a.y, b.y, c.y}), y1 = std::max({a.y, b.y, c.y});
        const Point2 v[3] = {a, b, c};
        for (int j = cell(y0 - margin); j <= cell(y1 + margin); ++j)
            for (int i = cell(x0 - margin); i <= cell(x1 + margin); ++i) {
                const float cx0 = -radius_ + float(i) * cell_ - margin,
                            cx1 = cx0 + cell_ + 2.f * margin;
                const float cy0 = -radius_ + float(j) * cell_ - margin,
                            cy1 = cy0 + cell_ + 2.f * margin;
                bool separated = false;
                for (int e = 0; e < 3 && !separated; ++e) {
                    const Point2 p = v[e], q = v[(e + 1) % 3], r = v[(e + 2) % 3];
                    const float nx = p.y - q.y, ny = q.x - p.x;  // the edge's normal
                    const float edge = nx * p.x + ny * p.y, other = nx * r.x + ny * r.y;
                    // The cell's corner farthest towards the triangle's side of the edge.
                    const float toward = other >= edge ? 1.f : -1.f;
                    const float corner =
                        std::max(toward * (nx * cx0 + ny * cy0),
                                 std::max(toward * (nx * cx1 + ny * cy0),
                                          std::max(toward * (nx * cx0 + ny * cy1),
                                                   toward * (nx * cx1 + ny * cy1))));
                    separated = corner < toward * edge;
                }
                if (!separated) mark[std::size_t(j) * std::size_t(res_) + i] = 1;
            }
    };
    auto project = [&](const Vec3& p) {
        const Vec3 d = p - center;
        return Point2{dot(d, s), dot(d, t)};
    };
    for (uint32_t g = 0; g < scene.objects.size(); ++g) {
        const Object& o = scene.objects[g];
        if (o.kind == ObjectKind::Sphere && o.instance < 0) {
            const Sphere& sp = scene.spheres[o.index];
            const Point2 c = project(sp.center);
            mark_box(c.x - sp.radius, c.x + sp.radius, c.y - sp.radius, c.y + sp.radius);
        } else if (o.kind == ObjectKind::Mesh) {
            const TriangleMesh& m = scene.meshes[o.index];
            for (uint32_t tri = 0; tri < m.indices.size() / 3; ++tri) {
                Vec3 p[3];
                scene.world_corners(g, tri, p[0], p[1], p[2]);
                mark_triangle(project(p[0]), project(p[1]), project(p[2]));
            }
        } else {
            // Anything else (an instanced sphere): its world box's eight corners.
            const Bounds3 b = scene.object_bounds(g);
            float x0 = kInfinity, x1 = -kInfinity, y0 = kInfinity, y1 = -kInfinity;
            for (int k = 0; k < 8; ++k) {
                const Point2 c = project(Vec3{k & 1 ? b.hi.x : b.lo.x, k & 2 ? b.hi.y : b.lo.y,
                                              k & 4 ? b.hi.z : b.lo.z});
                x0 = std::min(x0, c.x), x1 = std::max(x1, c.x);
                y0 = std::min(y0, c.y), y1 = std::max(y1, c.y);
            }
            mark_box(x0, x1, y0, y1);
        }
    }
    for (std::size_t k = 0; k < mark.size(); ++k)
        if (mark[k]) kept_.push_back(uint32_t(k));
}

Point2 ProjectionMap::sample(Point2 u) const {
    // The cell by u.x, stretched back to [0, 1) for the position across it.
    const float n = float(kept_.size());
    const std::size_t k = std::min(kept_.size() - 1, std::size_t(u.x * n));
    const float ux = std::min(u.x * n - float(k), 0x1.fffffep-1f);
    const uint32_t c = kept_[k];
    const int i = int(c % uint32_t(res_)), j = int(c / uint32_t(res_));
    return {-radius_ + (float(i) + ux) * cell_, -radius_ + (float(j) + u.y) * cell_};
}

}  // namespace foton
