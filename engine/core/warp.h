#pragma once
// Warps from the unit square to the domains Monte Carlo integration needs, each with the
// density of the points it produces. Local directions are in a frame whose z axis is the
// surface normal.
#include <cmath>

#include "math.h"
#include "sampler.h"

namespace foton::warp {

// Shirley–Chiu concentric map: square -> unit disc, area preserving, low distortion.
inline Point2 concentric_disc(Point2 u) {
    const float a = 2.f * u.x - 1.f, b = 2.f * u.y - 1.f;
    if (a == 0.f && b == 0.f) return {0.f, 0.f};
    float r, phi;
    if (std::fabs(a) > std::fabs(b)) {
        r = a;
        phi = 0.25f * kPi * (b / a);
    } else {
        r = b;
        phi = 0.5f * kPi - 0.25f * kPi * (a / b);
    }
    return {r * std::cos(phi), r * std::sin(phi)};
}

// Cosine-weighted hemisphere (Malley's method); pdf = cos(theta) / pi.
inline Vec3 cosine_hemisphere(Point2 u) {
    const Point2 d = concentric_disc(u);
    const float z = std::sqrt(std::max(0.f, 1.f - d.x * d.x - d.y * d.y));
    return {d.x, d.y, z};
}
inline float cosine_hemisphere_pdf(float cos_theta) {
    return cos_theta > 0.f ? cos_theta * kInvPi : 0.f;
}

// Uniform sphere of directions; pdf = 1 / (4 pi).
inline Vec3 uniform_sphere(Point2 u) {
    const float z = 1.f - 2.f * u.x;
    const float r = std::sqrt(std::max(0.f, 1.f - z * z));
    const float phi = 2.f * kPi * u.y;
    return {r * std::cos(phi), r * std::sin(phi), z};
}
inline constexpr float kUniformSpherePdf = 1.f / (4.f * kPi);

// Uniform over the cone of directions within acos(cos_max) of +z; pdf = 1 / (2 pi (1 - cos_max)).
inline Vec3 uniform_cone(Point2 u, float cos_max) {
    const float z = 1.f - u.x * (1.f - cos_max);
    const float r = std::sqrt(std::max(0.f, 1.f - z * z));
    const float phi = 2.f * kPi * u.y;
    return {r * std::cos(phi), r * std::sin(phi), z};
}
inline float uniform_cone_pdf(float cos_max) {
    return 1.f / (2.f * kPi * (1.f - cos_max));
}

// Uniform over a triangle: barycentrics (b1, b2) of the second and third vertex
// (Heitz 2019, low distortion; pdf = 1 / area).
inline Point2 uniform_triangle(Point2 u) {
    float b0, b1;
    if (u.x < u.y) {
        b0 = 0.5f * u.x;
        b1 = u.y - b0;
    } else {
        b1 = 0.5f * u.y;
        b0 = u.x - b1;
    }
    return {b1, 1.f - b0 - b1};
}

// A frame (s, t, n) around a unit normal, for going between world and local directions.
struct Frame {
    Vec3 s, t, n;
    Frame() = default;
    explicit Frame(const Vec3& normal) : n(normal) { orthonormal_basis(n, s, t); }
    // Around `normal` with s along `tangent` (unit and perpendicular to it) and t = n x s, as
    // pbrt-v4's shading frame: anisotropic BSDFs follow the surface's dp/du. A zero tangent
    // gives the basis of Frame(normal).
    Frame(const Vec3& normal, const Vec3& tangent) : n(normal) {
        if (tangent.x == 0.f && tangent.y == 0.f && tangent.z == 0.f) {
            orthonormal_basis(n, s, t);
        } else {
            s = tangent;
            t = cross(n, s);
        }
    }
    Vec3 to_local(const Vec3& v) const { return {dot(v, s), dot(v, t), dot(v, n)}; }
    Vec3 to_world(const Vec3& v) const { return s * v.x + t * v.y + n * v.z; }
};

}  // namespace foton::warp
