#include "surface.h"

#include <algorithm>
#include <cmath>

namespace foton {

namespace {

// dp/du of a triangle from its corners and their texture coordinates (0 when the uv are
// degenerate: the map then has no tangent there and is not applied).
Vec3 triangle_dpdu(const Vec3& p0, const Vec3& p1, const Vec3& p2, Point2 t0, Point2 t1,
                   Point2 t2) {
    const float du1 = t1.x - t0.x, dv1 = t1.y - t0.y, du2 = t2.x - t0.x, dv2 = t2.y - t0.y;
    const float det = du1 * dv2 - dv1 * du2;
    if (std::fabs(det) < 1e-12f) return {0.f, 0.f, 0.f};
    return ((p1 - p0) * dv2 - (p2 - p0) * dv1) * (1.f / det);
}

// The shading normal n turned by a tangent-space normal map's texel: (2 rgb - 1) in the frame
// of T = dpdu made perpendicular to n, B = n x T, n.
Vec3 normal_mapped(const Vec3& n, const Vec3& dpdu, const RGB& texel) {
    const Vec3 t = dpdu - n * dot(n, dpdu);
    const float len = length(t);
    if (!(len > 1e-12f)) return n;
    const Vec3 tx = t / len, bx = cross(n, tx);
    const Vec3 m =
        tx * (2.f * texel.r - 1.f) + bx * (2.f * texel.g - 1.f) + n * (2.f * texel.b - 1.f);
    const float ml = length(m);
    return ml > 0.f ? m / ml : n;
}

}  // namespace

SurfacePoint surface_at(const Scene& scene, uint32_t geom, uint32_t prim, float t, float u, float v,
                        const Vec3& origin, const Vec3& dir) {
    SurfacePoint sp;
    const Object& obj = scene.objects[geom];
    const Material& mat = scene.materials[obj.material];
    const bool textured = mat.texture >= 0 || mat.normal_map >= 0;
    Vec3 n_geom, n_shade, dpdu{0, 0, 0};
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
            // pbrt's default parametrisation of a triangle: (0, 0), (1, 0), (1, 1).
            Point2 t0{0.f, 0.f}, t1{1.f, 0.f}, t2{1.f, 1.f};
            if (!m.uvs.empty()) {
                t0 = {m.uvs[2 * ix[0]], m.uvs[2 * ix[0] + 1]};
                t1 = {m.uvs[2 * ix[1]], m.uvs[2 * ix[1] + 1]};
                t2 = {m.uvs[2 * ix[2]], m.uvs[2 * ix[2] + 1]};
            }
            const float w = 1.f - u - v;
            sp.uv = {t0.x * w + t1.x * u + t2.x * v, t0.y * w + t1.y * u + t2.y * v};
            if (mat.normal_map >= 0) dpdu = triangle_dpdu(p0, p1, p2, t0, t1, t2);
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
            dpdu = {-n_geom.y, n_geom.x, 0.f};  // along phi (zero at the poles)
        }
    }
    if (mat.normal_map >= 0)
        n_shade = normal_mapped(
            n_shade, dpdu,
            scene.textures[std::size_t(mat.normal_map)].eval(scene.texture_images, sp.uv));
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
