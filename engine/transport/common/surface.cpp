#include "surface.h"

#include <algorithm>
#include <cmath>

#include "shading_normal.h"

namespace foton {

namespace {

// The width in uv of a pixel's footprint at p (normal n) on a surface of partials dpdu, dpdv,
// from the camera as pbrt-v4 approximates it at every hit, whatever the path: the pixel's
// width at the point's distance, stretched by the slant (to at most 10x), over the shorter
// of the uv partials.
float footprint_at(const Camera& cam, const Vec3& p, const Vec3& n, const Vec3& dpdu,
                   const Vec3& dpdv) {
    const Vec3 to = p - cam.eye;
    const float dist = length(to);
    float w;
    if (cam.type == CameraType::Orthographic)
        w = cam.pixel_size;
    else if (cam.type == CameraType::Perspective)
        w = dist * cam.pixel_size / cam.d;
    else
        w = dist * cam.pixel_angle();
    const float slant = dist > 0.f ? std::fabs(dot(to, n)) / dist : 1.f;
    const float per_uv = std::min(length(dpdu), length(dpdv));
    if (!(per_uv > 0.f) || !std::isfinite(w)) return 0.f;
    return w / std::max(slant, 0.1f) / per_uv;
}

// The uv steps of one pixel along the image's x and y at p (pbrt-v4's approximation of the
// camera's ray differentials at every hit): the neighbouring pixels' rays met in the tangent
// plane at p, that offset written in dp/du and dp/dv by least squares. Zero where the
// camera has no such neighbours (the panoramic ones: footprint alone then).
void pixel_uv_steps(const Camera& cam, const Vec3& p, const Vec3& n, const Vec3& dpdu,
                    const Vec3& dpdv, Point2& duvdx, Point2& duvdy) {
    Vec3 dir;
    float scale;
    if (cam.type == CameraType::Perspective) {
        const Vec3 to = p - cam.eye;
        const float dist = length(to);
        if (!(dist > 0.f)) return;
        dir = to / dist;
        scale = dot(to, cam.w) * cam.pixel_size / cam.d;
    } else if (cam.type == CameraType::Orthographic) {
        dir = cam.w;
        scale = cam.pixel_size;
    } else {
        return;
    }
    const float dn = dot(dir, n);
    if (std::fabs(dn) < 1e-4f) return;
    const float a00 = dot(dpdu, dpdu), a01 = dot(dpdu, dpdv), a11 = dot(dpdv, dpdv);
    const float det = a00 * a11 - a01 * a01;
    if (!(std::fabs(det) > 1e-20f) || !std::isfinite(det)) return;
    auto step = [&](const Vec3& offset) {
        const Vec3 dp = offset - dir * (dot(offset, n) / dn);
        const float b0 = dot(dpdu, dp), b1 = dot(dpdv, dp);
        const float du = (a11 * b0 - a01 * b1) / det, dv = (a00 * b1 - a01 * b0) / det;
        return std::isfinite(du) && std::isfinite(dv) ? Point2{du, dv} : Point2{0.f, 0.f};
    };
    duvdx = step(cam.u * scale);
    duvdy = step(cam.v * scale);
}

}  // namespace

SurfacePoint surface_at(const Scene& scene, uint32_t geom, uint32_t prim, float t, float u, float v,
                        const Vec3& origin, const Vec3& dir) {
    SurfacePoint sp;
    const Object& obj = scene.objects[geom];
    const Material& mat = scene.materials[obj.material];
    // An anisotropic BSDF's frame follows dp/du: the parametrisation is needed then too.
    const bool tangent = mat.needs_tangent();
    const bool textured = mat.needs_uv() || tangent;
    Vec3 n_geom, n_shade;
    ShadingGeometry g;     // the parametrisation a normal or bump map reads
    bool perturb = false;  // g is set
    float curve_width = 0.f;
    bool second_set = false;  // sp.uv2 is a mesh's second uv set (else it is sp.uv)
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
        if (mat.vertex_colored) sp.vertex_color = m.color_at(prim, u, v);
        if (textured) {
            const uint32_t* ix = &m.indices[3 * prim];
            Point2 t0, t1, t2;
            m.corner_uvs(prim, t0, t1, t2);
            const float w = 1.f - u - v;
            sp.uv = {t0.x * w + t1.x * u + t2.x * v, t0.y * w + t1.y * u + t2.y * v};
            if (!m.uvs2.empty()) {
                Point2 s0, s1, s2;
                m.corner_uvs(prim, s0, s1, s2, 1);
                sp.uv2 = {s0.x * w + s1.x * u + s2.x * v, s0.y * w + s1.y * u + s2.y * v};
                second_set = true;
                // A normal map on the second set turns in that set's tangent frame (the
                // footprint below is then that set's too: glTF's textures, the only ones on a
                // second set, are not MIP-mapped).
                if (mat.normal_map >= 0 &&
                    scene.textures[std::size_t(mat.normal_map)].uv.set == 1) {
                    t0 = s0, t1 = s1, t2 = s2;
                }
            }
            // The uv partials, for a perturbed frame and for MIP-mapped textures' footprint
            // (only scenes with such textures pay for it).
            const bool frame = mat.perturbs_normal() || tangent;
            const bool partials = (frame || scene.mip_mapped) &&
                                  triangle_partials(p0, p1, p2, t0, t1, t2, g.dpdu, g.dpdv);
            if (partials && scene.mip_mapped) {
                sp.footprint = footprint_at(scene.camera, sp.p, n_geom, g.dpdu, g.dpdv);
                pixel_uv_steps(scene.camera, sp.p, n_geom, g.dpdu, g.dpdv, sp.duvdx, sp.duvdy);
            }
            if (frame) {
                g.n = n_shade;
                if (partials) {
                    if (obj.smooth) {
                        // pbrt-v4's shading tangents: dp/du made perpendicular to the
                        // interpolated normal, and that normal crossed with it.
                        const Vec3 ts = cross(n_shade, g.dpdu);
                        if (length_squared(ts) > 0.f) {
                            g.dpdu = cross(ts, n_shade);
                            g.dpdv = ts;
                        }
                        Vec3 n0 = m.vertex_normal(ix[0]), n1 = m.vertex_normal(ix[1]),
                             n2 = m.vertex_normal(ix[2]);
                        if (in) {
                            n0 = in->to_world.normal(n0);
                            n1 = in->to_world.normal(n1);
                            n2 = in->to_world.normal(n2);
                        }
                        if (!triangle_partials(n0, n1, n2, t0, t1, t2, g.dndu, g.dndv))
                            g.dndu = g.dndv = {0.f, 0.f, 0.f};
                    }
                    perturb = mat.perturbs_normal();
                } else if (mat.bump >= 0) {
                    // No tangents from the uv: any pair, as pbrt-v4 does.
                    orthonormal_basis(n_shade, g.dpdu, g.dpdv);
                    perturb = true;
                }
            }
        }
    } else if (obj.kind == ObjectKind::Curves) {
        const CurvePoint c = curve_point_at(scene.curves[obj.index], prim, u, v, dir);
        sp.p = origin + dir * t;
        n_geom = n_shade = c.n;
        sp.uv = {c.u, v};
        g.n = c.n;
        g.dpdu = c.dpdu;
        g.dpdv = c.dpdv;
        perturb = mat.perturbs_normal();
        curve_width = c.width;
    } else if (obj.kind == ObjectKind::Shape) {
        const AnalyticShape& shape = scene.shapes[obj.index];
        const ShapePrimitive& leaf = shape.shapes()[prim_shape(prim)];
        sp.p = origin + dir * t;
        const ShapeSurface ss = shape_surface(leaf, prim_part(prim), leaf.to_object.point(sp.p));
        // A surface subtracted in a CSG tree bounds the result from the other side.
        const float side = shape.inverted(prim_shape(prim)) ? -1.f : 1.f;
        const float det = leaf.to_world.determinant();
        n_geom = n_shade = leaf.to_world.normal(ss.n) * side;
        sp.uv = ss.uv;
        g.n = n_geom;
        g.dpdu = leaf.to_world.vector(ss.dpdu);
        g.dpdv = leaf.to_world.vector(ss.dpdv);
        // The unit normal's derivatives turn with the placement but do not scale (exact for
        // rotations and uniform scales).
        const float unscale = side / std::cbrt(std::fabs(det));
        g.dndu = leaf.to_world.vector(ss.dndu) * unscale;
        g.dndv = leaf.to_world.vector(ss.dndv) * unscale;
        perturb = mat.perturbs_normal();
    } else {
        const Sphere& s = scene.spheres[obj.index];
        sp.p = origin + dir * t;
        n_geom = (sp.p - s.center) / s.radius;
        n_shade = n_geom;
        if (textured) {
            sp.uv = sphere_uv(n_geom);
            const float sin_theta = std::sqrt(n_geom.x * n_geom.x + n_geom.y * n_geom.y);
            // |dp/du| = 2 pi r sin theta, |dp/dv| = pi r (sphere_uv's parametrisation).
            const float r = s.radius;
            if (scene.mip_mapped) {
                sp.footprint =
                    footprint_at(scene.camera, sp.p, n_geom,
                                 Vec3{2.f * kPi * r * std::max(sin_theta, 1e-3f), 0.f, 0.f},
                                 Vec3{kPi * r, 0.f, 0.f});
                if (sin_theta > 1e-6f)
                    pixel_uv_steps(scene.camera, sp.p, n_geom,
                                   Vec3{-n_geom.y, n_geom.x, 0.f} * (2.f * kPi * r),
                                   Vec3{n_geom.z * n_geom.x / sin_theta,
                                        n_geom.z * n_geom.y / sin_theta, -sin_theta} *
                                       (-kPi * r),
                                   sp.duvdx, sp.duvdy);
            }
            if ((mat.perturbs_normal() || tangent) && sin_theta > 1e-6f) {
                // pbrt's partials of that parametrisation; the normal turns as the point
                // moves (dn = dp / r).
                const float r = s.radius;
                g.n = n_geom;
                g.dpdu = Vec3{-n_geom.y, n_geom.x, 0.f} * (2.f * kPi * r);
                g.dpdv = Vec3{n_geom.z * n_geom.x / sin_theta, n_geom.z * n_geom.y / sin_theta,
                              -sin_theta} *
                         (-kPi * r);
                g.dndu = g.dpdu / r;
                g.dndv = g.dpdv / r;
                perturb = mat.perturbs_normal();
            }
        }
    }
    if (!second_set) sp.uv2 = sp.uv;
    if (perturb) {
        TexPoint at{sp.uv, sp.p, n_geom};
        at.uv2 = sp.uv2;
        n_shade =
            mat.normal_map >= 0
                ? normal_mapped(
                      n_shade, g.dpdu,
                      scene.textures[std::size_t(mat.normal_map)].eval(scene.texture_images, at),
                      mat.normal_scale)
                : bump_mapped(g, scene.textures[std::size_t(mat.bump)], scene.texture_images, at);
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
    if (tangent) {
        // dp/du in the final shading plane (after a bump, the unbumped dp/du projected).
        const Vec3 ts = g.dpdu - n_shade * dot(n_shade, g.dpdu);
        const float len = length(ts);
        if (len > 1e-12f && std::isfinite(len)) sp.ss = ts / len;
    }
    // A curve's hit lies on the ribbon through its axis: rays leave it a width away, outside
    // the fibre it stands for (pbrt-v4 bounds a curve point's error by the width too).
    sp.epsilon = std::max(offset_epsilon(sp.p, t), curve_width);
    return sp;
}

}  // namespace foton
