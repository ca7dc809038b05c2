// The surface of an analytic shape at a point: normal, (u, v) and partial derivatives, in the
// shape's object space (pbrt-v4's parametrisations for the disk, cylinder, cone and sphere).
#include <algorithm>
#include <cmath>

#include "analytic_shape.h"

namespace foton {

namespace {

float shape_angle(float x, float y) {
    float phi = std::atan2(y, x);
    if (phi < 0.f) phi += 2.f * kPi;
    return phi;
}

// A disk-like face in a plane z = const of normal (0, 0, nz), u round, v inwards.
ShapeSurface polar_face(const Vec3& p, float radius, float inner, float phi_max, float nz) {
    ShapeSurface s;
    const float rho = std::sqrt(p.x * p.x + p.y * p.y);
    s.n = {0.f, 0.f, nz};
    s.uv = {shape_angle(p.x, p.y) / phi_max, (radius - rho) / (radius - inner)};
    s.dpdu = Vec3{-p.y, p.x, 0.f} * phi_max;
    s.dpdv =
        rho > 0.f ? Vec3{p.x, p.y, 0.f} * ((inner - radius) / rho) : Vec3{inner - radius, 0, 0};
    s.dndu = s.dndv = {0.f, 0.f, 0.f};
    return s;
}

ShapeSurface box_face(const ShapePrimitive& sh, uint8_t part, const Vec3& p) {
    const int a = part / 2, b = (a + 1) % 3, c = (a + 2) % 3;
    const float* h = &sh.half.x;
    const float* q = &p.x;
    ShapeSurface s;
    s.n = {0.f, 0.f, 0.f};
    (&s.n.x)[a] = (part & 1) ? 1.f : -1.f;
    s.uv = {(q[b] + h[b]) / (2.f * h[b]), (q[c] + h[c]) / (2.f * h[c])};
    s.dpdu = s.dpdv = s.dndu = s.dndv = {0.f, 0.f, 0.f};
    (&s.dpdu.x)[b] = 2.f * h[b];
    (&s.dpdv.x)[c] = 2.f * h[c];
    return s;
}

}  // namespace

ShapeSurface shape_surface(const ShapePrimitive& sh, uint8_t part, const Vec3& p) {
    ShapeSurface s;
    s.dndv = {0.f, 0.f, 0.f};
    const float phi = shape_angle(p.x, p.y);
    switch (sh.type) {
        case ShapeType::Disk:
            return polar_face(p, sh.radius, sh.inner_radius, sh.phi_max, 1.f);
        case ShapeType::Box:
            return box_face(sh, part, p);
        case ShapeType::Cylinder:
        case ShapeType::Cone:
        case ShapeType::Paraboloid:
        case ShapeType::Hyperboloid: {
            if (part == 1) return polar_face(p, sh.radius, 0.f, 2.f * kPi, -1.f);
            if (part == 2) return polar_face(p, sh.radius, 0.f, 2.f * kPi, 1.f);
            const float H = sh.height, v = std::clamp(p.z / H, 0.f, 1.f);
            s.uv = {phi / sh.phi_max, v};
            s.dpdu = Vec3{-p.y, p.x, 0.f} * sh.phi_max;
            if (sh.type == ShapeType::Cylinder) {
                s.n = normalize(Vec3{p.x, p.y, 0.f});
                s.dpdv = {0.f, 0.f, H};
                s.dndu = Vec3{-s.n.y, s.n.x, 0.f} * sh.phi_max;
            } else if (sh.type == ShapeType::Paraboloid || sh.type == ShapeType::Hyperboloid) {
                // The gradient of x^2 + y^2 - g(z), and dp/dv along the generator rho(v).
                const float R = sh.radius, a = sh.inner_radius;
                float dg_dz, drho_dv;
                if (sh.type == ShapeType::Paraboloid) {
                    dg_dz = R * R / H;
                    const float rho = R * std::sqrt(v);
                    drho_dv = rho > 0.f ? R * R / (2.f * rho) : 0.f;
                } else {
                    const float w = 2.f * v - 1.f, k = R * R - a * a;
                    dg_dz = 4.f * k * w / H;
                    const float rho = std::sqrt(a * a + k * w * w);
                    drho_dv = rho > 0.f ? 2.f * k * w / rho : 0.f;
                }
                s.n = normalize(Vec3{2.f * p.x, 2.f * p.y, -dg_dz});
                s.dpdv = Vec3{std::cos(phi) * drho_dv, std::sin(phi) * drho_dv, H};
                s.dndu = Vec3{-s.n.y, s.n.x, 0.f} * sh.phi_max;
            } else {
                // The gradient of x^2 + y^2 - k^2 (H - z)^2; the normal only turns with phi.
                const float k = sh.radius / H;
                s.n = normalize(Vec3{std::cos(phi), std::sin(phi), k});
                s.dpdv = Vec3{-std::cos(phi) * sh.radius, -std::sin(phi) * sh.radius, H};
                s.dndu = Vec3{-s.n.y, s.n.x, 0.f} * sh.phi_max;
            }
            return s;
        }
        case ShapeType::Torus: {
            const float rho = std::sqrt(p.x * p.x + p.y * p.y);
            float theta = std::atan2(p.z, rho - sh.radius);
            if (theta < 0.f) theta += 2.f * kPi;
            const float ct = std::cos(theta), st = std::sin(theta), cp = std::cos(phi),
                        sp = std::sin(phi);
            s.n = {ct * cp, ct * sp, st};
            s.uv = {phi / (2.f * kPi), theta / (2.f * kPi)};
            s.dpdu = Vec3{-p.y, p.x, 0.f} * (2.f * kPi);
            s.dpdv = Vec3{-st * cp, -st * sp, ct} * (2.f * kPi * sh.minor_radius);
            s.dndu = Vec3{-s.n.y, s.n.x, 0.f} * (2.f * kPi);
            s.dndv = s.dpdv / sh.minor_radius;
            return s;
        }
        case ShapeType::Sphere: {
            const float r = sh.radius;
            s.n = p / r;
            const float nz = std::clamp(s.n.z, -1.f, 1.f);
            s.uv = {phi / (2.f * kPi), 1.f - std::acos(nz) / kPi};
            const float sin_theta = std::sqrt(s.n.x * s.n.x + s.n.y * s.n.y);
            s.dpdu = Vec3{-s.n.y, s.n.x, 0.f} * (2.f * kPi * r);
            s.dpdv =
                sin_theta > 1e-6f
                    ? Vec3{nz * s.n.x / sin_theta, nz * s.n.y / sin_theta, -sin_theta} * (-kPi * r)
                    : Vec3{0.f, 0.f, 0.f};
            s.dndu = s.dpdu / r;
            s.dndv = s.dpdv / r;
            return s;
        }
    }
    return s;
}

}  // namespace foton
