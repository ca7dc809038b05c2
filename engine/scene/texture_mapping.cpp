// Where a texture reads itself at a surface point: the surface's uv through the texture's
// UvMap, or, for pbrt-v4's mappings by position, the hit point taken into the texture's own
// space (the transform in force where the texture was declared): spherical (theta / pi,
// phi / 2 pi of the direction from the origin), cylindrical ((pi + atan2(y, x)) / 2 pi, z)
// and planar (offsets plus the point's components along two vectors).
#include <algorithm>
#include <cmath>

#include "texture.h"

namespace foton {

Point2 Texture::st(const TexPoint& at) const {
    if (mapping == TextureMapping::UV) return uv(at.uv_of(uv.set));
    const Vec3 q = to_texture.point(at.p);
    switch (mapping) {
        case TextureMapping::Spherical: {
            const float len = length(q);
            if (!(len > 0.f)) return {0.f, 0.f};
            const Vec3 d = q / len;
            float phi = std::atan2(d.y, d.x);
            if (phi < 0.f) phi += 2.f * kPi;
            return {std::acos(std::clamp(d.z, -1.f, 1.f)) / kPi, phi / (2.f * kPi)};
        }
        case TextureMapping::Cylindrical:
            return {(kPi + std::atan2(q.y, q.x)) / (2.f * kPi), q.z};
        case TextureMapping::Planar:
            return {uv.du + dot(q, plane_s), uv.dv + dot(q, plane_t)};
        case TextureMapping::UV:
            break;
    }
    return uv(at.uv);
}

}  // namespace foton
