#include "shading_normal.h"

#include <cmath>

namespace foton {

bool triangle_partials(const Vec3& q0, const Vec3& q1, const Vec3& q2, Point2 t0, Point2 t1,
                       Point2 t2, Vec3& dqdu, Vec3& dqdv) {
    const float du02 = t0.x - t2.x, dv02 = t0.y - t2.y, du12 = t1.x - t2.x, dv12 = t1.y - t2.y;
    const float det = du02 * dv12 - dv02 * du12;
    if (!(std::fabs(det) >= 1e-12f)) return false;
    const Vec3 dq02 = q0 - q2, dq12 = q1 - q2;
    const float inv = 1.f / det;
    dqdu = (dq02 * dv12 - dq12 * dv02) * inv;
    dqdv = (dq12 * du02 - dq02 * du12) * inv;
    return true;
}

Vec3 normal_mapped(const Vec3& n, const Vec3& dpdu, const RGB& texel, float scale) {
    const Vec3 t = dpdu - n * dot(n, dpdu);
    const float len = length(t);
    if (!(len > 1e-12f)) return n;
    const Vec3 tx = t / len, bx = cross(n, tx);
    const Vec3 m = (tx * (2.f * texel.r - 1.f) + bx * (2.f * texel.g - 1.f)) * scale +
                   n * (2.f * texel.b - 1.f);
    const float ml = length(m);
    return ml > 0.f ? m / ml : n;
}

Vec3 bump_mapped(const ShadingGeometry& g, const Texture& displacement,
                 const std::vector<TextureImage>& images, const TexPoint& at) {
    constexpr float kStep = 0.0005f;
    // The step moves the point too (textures mapped by position see it), as pbrt-v4's does.
    const Point2 uv = at.uv;
    const float d = displacement.eval_float(images, at);
    const float d_u = displacement.eval_float(
        images, TexPoint{{uv.x + kStep, uv.y}, at.p + g.dpdu * kStep, at.n});
    const float d_v = displacement.eval_float(
        images, TexPoint{{uv.x, uv.y + kStep}, at.p + g.dpdv * kStep, at.n});
    const Vec3 pu = g.dpdu + g.n * ((d_u - d) / kStep) + g.dndu * d;
    const Vec3 pv = g.dpdv + g.n * ((d_v - d) / kStep) + g.dndv * d;
    const Vec3 m = cross(pu, pv);
    const float len = length(m);
    if (!(len > 0.f) || !std::isfinite(len)) return g.n;
    const Vec3 nb = m / len;
    return dot(nb, g.n) < 0.f ? -nb : nb;
}

}  // namespace foton
