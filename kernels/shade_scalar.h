#pragma once
// What the scalar twins of the shading kernels share (diffuse_shade_scalar.cpp,
// specular_shade_scalar.cpp): 3-vectors, the surface reconstructed from the hit, the offset
// and the shading frame, the same IEEE operations in the same order as shade_lanes.h.
#include <algorithm>
#include <cmath>
#include <cstddef>

#include "diffuse_shade.h"
#include "diffuse_shade_math.h"

namespace foton::kern::scalar {

struct V3 {
    float x, y, z;
};
inline V3 operator+(V3 a, V3 b) {
    return {a.x + b.x, a.y + b.y, a.z + b.z};
}
inline V3 operator-(V3 a, V3 b) {
    return {a.x - b.x, a.y - b.y, a.z - b.z};
}
inline V3 operator*(V3 a, float s) {
    return {a.x * s, a.y * s, a.z * s};
}
inline float dot(V3 a, V3 b) {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}
inline V3 cross(V3 a, V3 b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
// p pushed off the surface along ng to the side w goes.
inline V3 offset(V3 p, V3 ng, float eps, V3 w) {
    return dot(w, ng) >= 0.f ? p + ng * eps : p - ng * eps;
}

inline V3 in3(const ShadeTable& v, uint32_t c, std::size_t i) {
    return V3{v.col(c)[i], v.col(c + 1)[i], v.col(c + 2)[i]};
}
inline void out3(const ShadeTable& v, uint32_t c, std::size_t i, V3 a) {
    v.col(c)[i] = a.x;
    v.col(c + 1)[i] = a.y;
    v.col(c + 2)[i] = a.z;
}

// The surface of lane i when kDvSurface is not 0 (a triangle's barycentric point and normals,
// or a sphere's), into the surface columns and kDvFront.
inline void reconstruct_surface_scalar(const ShadeTable& v, std::size_t i) {
    auto in3 = [&](uint32_t c, std::size_t k) { return scalar::in3(v, c, k); };
    auto out3 = [&](uint32_t c, std::size_t k, V3 a) { scalar::out3(v, c, k, a); };
    const float kind = v.col(kDvSurface)[i];
    if (kind == 0.f) return;
    // The surface from the hit: a triangle's barycentric point and normals, or a
    // sphere's.
    const float t = v.col(kDvT)[i], u = v.col(kDvU)[i], w_v = v.col(kDvV)[i];
    const V3 dir = in3(kDvWox, i) * -1.f;
    const V3 a0 = in3(kDvA0x, i), a1 = in3(kDvA1x, i), a2 = in3(kDvA2x, i);
    V3 p, ng, ns;
    if (kind == 3.f) {
        p = in3(kDvOx, i) + dir * t;
        ng = (p - a0) * (1.f / a1.x);
        ns = ng;
    } else {
        const float w = (1.f - u) - w_v;
        p = (a0 * w + a1 * u) + a2 * w_v;
        const V3 c = cross(a1 - a0, a2 - a0);
        ng = c * (1.f / std::sqrt(dot(c, c)));
        ns = ng;
        if (kind == 2.f) {
            const V3 m = (in3(kDvN0x, i) * w + in3(kDvN1x, i) * u) + in3(kDvN2x, i) * w_v;
            const float len = std::sqrt(dot(m, m));
            if (len > 0.f) ns = m * (1.f / len);
        }
    }
    const bool back = dot(ng, dir) >= 0.f;
    if (back) {
        ng = ng * -1.f;
        ns = ns * -1.f;
    }
    if (dot(ns, dir) >= 0.f) ns = ng;
    out3(kDvPx, i, p);
    out3(kDvNgx, i, ng);
    out3(kDvNsx, i, ns);
    v.col(kDvEps)[i] =
        kDiffuseOffset * (std::max({std::fabs(p.x), std::fabs(p.y), std::fabs(p.z)}) + t);
    v.col(kDvFront)[i] = back ? 0.f : 1.f;
}

// The frame (s, t, ns) around a unit shading normal (Duff et al. 2017).
inline void shading_frame(V3 ns, V3& s, V3& t) {
    const float sign = std::copysign(1.f, ns.z);
    const float a = -1.f / (sign + ns.z);
    const float b = ns.x * ns.y * a;
    s = V3{1.f + sign * ns.x * ns.x * a, sign * b, -sign * ns.x};
    t = V3{b, sign + ns.y * ns.y * a, -ns.y};
}

}  // namespace foton::kern::scalar
