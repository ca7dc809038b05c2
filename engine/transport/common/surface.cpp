#include "surface.h"

#include <algorithm>
#include <cmath>

namespace foton {

SurfacePoint surface_at(const Scene& scene, uint32_t geom, uint32_t prim, float t, float u, float v,
                        const Vec3& origin, const Vec3& dir) {
    SurfacePoint sp;
    const Object& obj = scene.objects[geom];
    const bool textured = scene.materials[obj.material].texture >= 0;
    Vec3 n_geom, n_shade;
    if (obj.kind == ObjectKind::Mesh) {
        const TriangleMesh& m = scene.meshes[obj.index];
        const Instance* in = scene.instance_of(geom);
        Vec3 p0, p1, p2;
        m.corners(prim, p0, p1, p2);
        // Barycentric position is more precise than o + t d far from the origin (for an
        // instance, the barycentric point of its own space, placed).
        sp.p = p0 * (1.f - u - v) + p1 * u + p2 * v;
        if (in) {
            sp.p = in->to_world.point(sp.p);
            p0 = in->to_world.point(p0);
            p1 = in->to_world.point(p1);
            p2 = in->to_world.point(p2);
        }
        n_geom = normalize(cross(p1 - p0, p2 - p0));
        // A mirroring placement turns the winding: the outward normal is the other one.
        if (in && in->to_world.determinant() < 0.f) n_geom = -n_geom;
        n_shade = n_geom;
        if (obj.smooth) {
            const uint32_t* ix = &m.indices[3 * prim];
            Vec3 ns = m.vertex_normal(ix[0]) * (1.f - u - v) + m.vertex_normal(ix[1]) * u +
                      m.vertex_normal(ix[2]) * v;
            if (in) ns = in->to_world.normal(ns);
            const float len = length(ns);
            if (len > 0.f) n_shade = ns / len;
        }
        if (textured) {
            const uint32_t* ix = &m.indices[3 * prim];
            if (m.uvs.empty()) {
                // pbrt's default parametrisation of a triangle: (0, 0), (1, 0), (1, 1).
                sp.uv = {u + v, v};
            } else {
                const float w = 1.f - u - v;
                sp.uv = {
                    m.uvs[2 * ix[0]] * w + m.uvs[2 * ix[1]] * u + m.uvs[2 * ix[2]] * v,
                    m.uvs[2 * ix[0] + 1] * w + m.uvs[2 * ix[1] + 1] * u + m.uvs[2 * ix[2] + 1] * v};
            }
        }
    } else {
        const Sphere& s = scene.spheres[obj.index];
        sp.p = origin + dir * t;
        n_geom = (sp.p - s.center) / s.radius;
        n_shade = n_geom;
        if (textured) {
            // pbrt's sphere: u = phi / 2 pi around z, v = 1 - theta / pi (1 at the top, +z).
            float phi = std::atan2(n_geom.y, n_geom.x);
            if (phi < 0.f) phi += 2.f * kPi;
            sp.uv = {phi / (2.f * kPi), 1.f - std::acos(std::clamp(n_geom.z, -1.f, 1.f)) / kPi};
        }
    }
    sp.front_face = dot(n_geom, dir) < 0.f;
    if (!sp.front_face) {
        n_geom = -n_geom;
        n_shade = -n_shade;
    }
    // An interpolated normal may lean past the true surface; keep it on the viewer's side.
    if (dot(n_shade, dir) >= 0.f) n_shade = n_geom;
    sp.ng = n_geom;
    sp.ns = n_shade;
    sp.epsilon = offset_epsilon(sp.p, t);
    return sp;
}

}  // namespace foton
