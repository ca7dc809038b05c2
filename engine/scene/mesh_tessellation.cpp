// Disks and cylinders as triangle meshes (pbrt-v4's `disk` and `cylinder` shapes). Straight
// in z and in r, so only the circle is approximated: its polygon's radius is scaled to keep the
// shape's area (and an emitting shape's power); with 256 segments around the full circle the
// surface lies within 0.02 % of the radius from the true one.
#include <algorithm>
#include <cmath>

#include "mesh_shapes.h"

namespace foton {

namespace {

// Segments over phi_max and the radius scale that keeps a polygon's area (disk) or
// perimeter (cylinder) equal to the circle's.
int segments_over(float phi_max, int segments) {
    return std::max(1, int(std::ceil(float(segments) * phi_max / (2.f * kPi))));
}

void push(TriangleMesh& m, const Vec3& p, const Vec3& n, float u, float v) {
    m.positions.insert(m.positions.end(), {p.x, p.y, p.z});
    m.normals.insert(m.normals.end(), {n.x, n.y, n.z});
    m.uvs.insert(m.uvs.end(), {u, v});
}

}  // namespace

TriangleMesh tessellate_disk(float height, float radius, float inner_radius, float phi_max,
                             int segments) {
    const int n = segments_over(phi_max, segments);
    const float step = phi_max / float(n);
    // A wedge of angle step has area r^2 sin(step) / 2 against the sector's r^2 step / 2.
    const float scale = std::sqrt(step / std::sin(step));
    TriangleMesh m;
    m.name = "disk";
    const Vec3 up{0, 0, 1};
    for (int i = 0; i <= n; ++i) {
        const float phi = step * float(i), u = float(i) / float(n);
        const float c = std::cos(phi), s = std::sin(phi);
        push(m, {radius * scale * c, radius * scale * s, height}, up, u, 0.f);
        push(m, {inner_radius * scale * c, inner_radius * scale * s, height}, up, u, 1.f);
    }
    for (uint32_t i = 0; i < uint32_t(n); ++i) {
        const uint32_t o0 = 2 * i, i0 = 2 * i + 1, o1 = 2 * i + 2, i1 = 2 * i + 3;
        m.indices.insert(m.indices.end(), {o0, o1, i1});
        if (inner_radius > 0.f) m.indices.insert(m.indices.end(), {o0, i1, i0});
    }
    return m;
}

TriangleMesh tessellate_cylinder(float radius, float z_min, float z_max, float phi_max,
                                 int segments) {
    const int n = segments_over(phi_max, segments);
    const float step = phi_max / float(n);
    // A chord of angle step is 2 r sin(step / 2) long against the arc's r step.
    const float scale = step / (2.f * std::sin(0.5f * step));
    TriangleMesh m;
    m.name = "cylinder";
    for (int i = 0; i <= n; ++i) {
        const float phi = step * float(i), u = float(i) / float(n);
        const Vec3 out{std::cos(phi), std::sin(phi), 0.f};
        const Vec3 p{radius * scale * out.x, radius * scale * out.y, 0.f};
        push(m, {p.x, p.y, z_min}, out, u, 0.f);
        push(m, {p.x, p.y, z_max}, out, u, 1.f);
    }
    for (uint32_t i = 0; i < uint32_t(n); ++i) {
        const uint32_t b0 = 2 * i, t0 = 2 * i + 1, b1 = 2 * i + 2, t1 = 2 * i + 3;
        m.indices.insert(m.indices.end(), {b0, b1, t1, b0, t1, t0});
    }
    return m;
}

}  // namespace foton
