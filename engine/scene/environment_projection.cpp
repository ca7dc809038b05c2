#include "environment_projection.h"

#include <algorithm>
#include <cmath>

#include "engine/core/warp.h"
#include "scene.h"

namespace foton {

namespace {

// The boxes of the cells of a kVoxels^3 grid over the scene's bounds that some object's box
// (a triangle's, for meshes) overlaps: a conservative outline of the geometry that a few
// hundred boxes describe, whatever the triangle count.
std::vector<Bounds3> occupied_voxels(const Scene& scene, int n) {
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
    // Greedy merging into boxes (grow along x, then z, then y while every cell is occupied and
    // not yet taken): the same union in a few dozen boxes instead of thousands of voxels.
    const Vec3 cell{size.x / float(n), size.y / float(n), size.z / float(n)};
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
    auto edge = [&](int k, int axis) {
        return k == n ? all.hi[axis] : lo[axis] + cell[axis] * float(k);
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

// The direction of cube face f (axis f / 2, sign by f's parity) at face coordinates (u, v) in
// [-1, 1]^2, not normalised.
Vec3 face_direction(int f, float u, float v) {
    const int a = f / 2;
    Vec3 d;
    d[a] = f % 2 == 0 ? 1.f : -1.f;
    d[(a + 1) % 3] = u;
    d[(a + 2) % 3] = v;
    return d;
}

}  // namespace

void EnvironmentProjection::build(const Scene& scene, const Vec3& center, float radius) {
    bins_.clear();
    center_ = center;
    radius_ = radius;
    const std::vector<Bounds3> boxes = occupied_voxels(scene, kVoxels);
    if (boxes.empty() || !(radius > 0.f)) return;
    const int n = kFaceRes;
    bins_.resize(std::size_t(6 * n * n));
    for (int f = 0; f < 6; ++f)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                Bin& b = bins_[(std::size_t(f) * std::size_t(n) + std::size_t(j)) * std::size_t(n) +
                               std::size_t(i)];
                const float step = 2.f / float(n);
                const float u0 = -1.f + step * float(i), v0 = -1.f + step * float(j);
                b.c = normalize(face_direction(f, u0 + 0.5f * step, v0 + 0.5f * step));
                const warp::Frame fr(b.c);
                b.s = fr.s;
                b.t = fr.t;
                // The bin's widest angle from c is at a corner (a cube cell is convex in the
                // face plane, and the angle grows with the distance from c's point there).
                float cos_min = 1.f;
                for (int k = 0; k < 4; ++k) {
                    const Vec3 corner = normalize(
                        face_direction(f, u0 + (k & 1 ? step : 0.f), v0 + (k & 2 ? step : 0.f)));
                    cos_min = std::min(cos_min, dot(corner, b.c));
                }
                const float tan_max = std::sqrt(std::max(0.f, 1.f - cos_min * cos_min)) / cos_min;
                // A small margin over the exact shift for rounding, as the directional map's.
                const float grow = radius * tan_max * 1.001f + 1e-4f * radius;
                b.map.build(boxes, b.s, b.t, center, radius * (1.f + tan_max) * 1.001f, grow,
                            kMapRes);
            }
}

std::size_t EnvironmentProjection::bin_of(const Vec3& wi) const {
    const float ax = std::fabs(wi.x), ay = std::fabs(wi.y), az = std::fabs(wi.z);
    const int a = ax >= ay && ax >= az ? 0 : ay >= az ? 1 : 2;
    const float major = std::fabs(wi[a]);
    const int f = 2 * a + (wi[a] >= 0.f ? 0 : 1);
    const int n = kFaceRes;
    auto cell = [&](float c) {
        return std::clamp(int(std::floor((c / major + 1.f) * 0.5f * float(n))), 0, n - 1);
    };
    const int i = cell(wi[(a + 1) % 3]), j = cell(wi[(a + 2) % 3]);
    return (std::size_t(f) * std::size_t(n) + std::size_t(j)) * std::size_t(n) + std::size_t(i);
}

void EnvironmentProjection::sample(const Vec3& wi, Point2 u, Vec3& origin, float& pdf_pos) const {
    const Bin& b = bins_[bin_of(wi)];
    const Point2 q = b.map.sample(u);
    const Vec3 on_plane = center_ + b.s * q.x + b.t * q.y;
    // Upstream along wi past every point of the bounding sphere on the ray's line.
    const float back = (radius_ + length(on_plane - center_)) * 1.01f;
    origin = on_plane + wi * back;
    pdf_pos = 1.f / (b.map.area() * std::fabs(dot(b.c, wi)));
}

float EnvironmentProjection::pdf_pos(const Vec3& wi) const {
    const Bin& b = bins_[bin_of(wi)];
    return 1.f / (b.map.area() * std::fabs(dot(b.c, wi)));
}

bool EnvironmentProjection::covers(const Vec3& wi, const Vec3& p) const {
    const Bin& b = bins_[bin_of(wi)];
    // Where the line through p along wi crosses the bin's plane (through the centre, across c).
    const Vec3 d = p - center_;
    const Vec3 x = d - wi * (dot(d, b.c) / dot(wi, b.c));
    return b.map.kept({dot(x, b.s), dot(x, b.t)});
}

float EnvironmentProjection::kept_fraction() const {
    if (bins_.empty()) return 1.f;
    double sum = 0.0;
    for (const Bin& b : bins_) sum += double(b.map.area());
    return float(sum / double(bins_.size()) / (kPi * double(radius_) * double(radius_)));
}

}  // namespace foton
