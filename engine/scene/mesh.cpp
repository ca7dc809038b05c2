#include "mesh.h"

#include <cmath>

namespace foton {

Bounds3 TriangleMesh::bounds() const {
    Bounds3 b;
    for (uint32_t i : indices) b.extend(vertex(i));
    return b;
}

void TriangleMesh::compute_smooth_normals() {
    std::vector<Vec3> acc(num_vertices());
    for (std::size_t t = 0; t < num_triangles(); ++t) {
        Vec3 p0, p1, p2;
        corners(uint32_t(t), p0, p1, p2);
        const Vec3 n = cross(p1 - p0, p2 - p0);  // length = 2 * area: area weighting
        for (int k = 0; k < 3; ++k) acc[indices[3 * t + k]] += n;
    }
    normals.assign(positions.size(), 0.f);
    for (std::size_t i = 0; i < acc.size(); ++i) {
        const float len = length(acc[i]);
        const Vec3 n = len > 0.f ? acc[i] / len : Vec3{0, 0, 0};
        normals[3 * i] = n.x;
        normals[3 * i + 1] = n.y;
        normals[3 * i + 2] = n.z;
    }
}

void TriangleMesh::transform(const Affine& xf) {
    for (std::size_t i = 0; i < num_vertices(); ++i) {
        const Vec3 p = xf.point(vertex(uint32_t(i)));
        positions[3 * i] = p.x;
        positions[3 * i + 1] = p.y;
        positions[3 * i + 2] = p.z;
    }
    if (!normals.empty()) {
        for (std::size_t i = 0; i < num_vertices(); ++i) {
            const Vec3 n = xf.normal(vertex_normal(uint32_t(i)));
            normals[3 * i] = n.x;
            normals[3 * i + 1] = n.y;
            normals[3 * i + 2] = n.z;
        }
    }
    // A mirroring transform flips the winding; swap two corners to keep normals outward.
    if (xf.determinant() < 0.f)
        for (std::size_t t = 0; t < num_triangles(); ++t)
            std::swap(indices[3 * t + 1], indices[3 * t + 2]);
}

bool Sphere::transform(const Affine& xf) {
    const float sx = length(xf.vector({1, 0, 0})), sy = length(xf.vector({0, 1, 0})),
                sz = length(xf.vector({0, 0, 1}));
    if (std::fabs(sx - sy) > 1e-5f * sx || std::fabs(sx - sz) > 1e-5f * sx) return false;
    center = xf.point(center);
    radius *= sx;
    return true;
}

bool intersect_sphere(const Sphere& s, const Vec3& o, const Vec3& d, float tmin, float tmax,
                      float& t) {
    const Vec3 f = o - s.center;
    const float a = dot(d, d);
    const float b = dot(f, d);
    // Discriminant via |f - (f.d/a) d|^2 avoids cancellation for distant spheres.
    const Vec3 l = f - d * (b / a);
    const float disc = s.radius * s.radius - dot(l, l);
    if (disc < 0.f) return false;
    const float q = -(b + std::copysign(std::sqrt(a * disc), b));
    const float c = dot(f, f) - s.radius * s.radius;
    float t0 = q / a;
    float t1 = q != 0.f ? c / q : t0;
    if (t0 > t1) std::swap(t0, t1);
    if (t0 > tmin && t0 < tmax) {
        t = t0;
        return true;
    }
    if (t1 > tmin && t1 < tmax) {
        t = t1;
        return true;
    }
    return false;
}

}  // namespace foton
