#include "projection_map.h"

#include <algorithm>
#include <cmath>

#include "scene.h"

namespace foton {

// The convex hull of points, counter-clockwise (Andrew's monotone chain).
std::vector<Point2> convex_hull(std::vector<Point2> p) {
    std::sort(p.begin(), p.end(), [](const Point2& a, const Point2& b) {
        return a.x < b.x || (a.x == b.x && a.y < b.y);
    });
    auto turn = [](const Point2& o, const Point2& a, const Point2& b) {
        return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
    };
    std::vector<Point2> h(2 * p.size());
    std::size_t k = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
        while (k >= 2 && turn(h[k - 2], h[k - 1], p[i]) <= 0.f) --k;
        h[k++] = p[i];
    }
    for (std::size_t i = p.size() - 1, lower = k + 1; i-- > 0;) {
        while (k >= lower && turn(h[k - 2], h[k - 1], p[i]) <= 0.f) --k;
        h[k++] = p[i];
    }
    h.resize(k > 1 ? k - 1 : k);
    return h;
}

// Marks the cells of `mark` (res x res, of side `cell` from (-half, -half)) that the convex
// polygon `hull` (counter-clockwise; with fewer than 3 points, its box) overlaps, each cell grown
// by `grow` on every side: those in its box that no edge's line separates from it (the
// separating axis test in 2D).
void mark_convex(const std::vector<Point2>& hull, float grow, int res, float half, float cell,
                 std::vector<uint8_t>& mark) {
    auto index = [&](float v) {
        return std::clamp(int(std::floor((v + half) / cell)), 0, res - 1);
    };
    float x0 = kInfinity, x1 = -kInfinity, y0 = kInfinity, y1 = -kInfinity;
    for (const Point2& q : hull) {
        x0 = std::min(x0, q.x), x1 = std::max(x1, q.x);
        y0 = std::min(y0, q.y), y1 = std::max(y1, q.y);
    }
    for (int j = index(y0 - grow); j <= index(y1 + grow); ++j)
        for (int i = index(x0 - grow); i <= index(x1 + grow); ++i) {
            const float cx0 = -half + float(i) * cell - grow, cx1 = cx0 + cell + 2.f * grow;
            const float cy0 = -half + float(j) * cell - grow, cy1 = cy0 + cell + 2.f * grow;
            bool separated = false;
            for (std::size_t e = 0; e < hull.size() && hull.size() >= 3 && !separated; ++e) {
                const Point2 p = hull[e], q = hull[(e + 1) % hull.size()];
                const float nx = q.y - p.y, ny = p.x - q.x;  // outward
                // The cell's corner least far out along the edge's normal.
                separated = std::min(nx * (cx0 - p.x), nx * (cx1 - p.x)) +
                                std::min(ny * (cy0 - p.y), ny * (cy1 - p.y)) >
                            0.f;
            }
            if (!separated) mark[std::size_t(j) * std::size_t(res) + std::size_t(i)] = 1;
        }
}

void ProjectionMap::build(const Scene& scene, const Vec3& s, const Vec3& t, const Vec3& center,
                          float radius, int res) {
    res_ = std::min(res, 256);  // 16-bit cell indices
    radius_ = radius;
    cell_ = 2.f * radius / float(res_);
    kept_.clear();
    std::vector<uint8_t> mark(std::size_t(res_) * std::size_t(res_), 0);
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
    // Marks the cells a projected triangle overlaps (grown by the margin).
    auto mark_triangle = [&](Point2 a, Point2 b, Point2 c) {
        mark_convex(convex_hull({a, b, c}), margin, res_, radius_, cell_, mark);
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
        if (mark[k]) kept_.push_back(uint16_t(k));
}

void ProjectionMap::build(const std::vector<Bounds3>& boxes, const Vec3& s, const Vec3& t,
                          const Vec3& center, float half, float grow, int res) {
    res_ = std::min(res, 256);  // 16-bit cell indices
    radius_ = half;
    cell_ = 2.f * half / float(res_);
    kept_.clear();
    std::vector<uint8_t> mark(std::size_t(res_) * std::size_t(res_), 0);
    std::vector<Point2> corners(8);
    for (const Bounds3& b : boxes) {
        for (int k = 0; k < 8; ++k) {
            const Vec3 d =
                Vec3{k & 1 ? b.hi.x : b.lo.x, k & 2 ? b.hi.y : b.lo.y, k & 4 ? b.hi.z : b.lo.z} -
                center;
            corners[k] = {dot(d, s), dot(d, t)};
        }
        // Its projection is the hull of its corners, grown by how far the bundle shifts it.
        mark_convex(convex_hull(corners), grow, res_, radius_, cell_, mark);
    }
    for (std::size_t k = 0; k < mark.size(); ++k)
        if (mark[k]) kept_.push_back(uint16_t(k));
}

bool ProjectionMap::kept(Point2 q) const {
    const int i = int(std::floor((q.x + radius_) / cell_)),
              j = int(std::floor((q.y + radius_) / cell_));
    if (i < 0 || j < 0 || i >= res_ || j >= res_) return false;
    return std::binary_search(kept_.begin(), kept_.end(), uint16_t(j * res_ + i));
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
