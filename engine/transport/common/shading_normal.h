#pragma once
// The shading normal a texture makes: a tangent-space normal map's, or a bump map's (the
// normal of the surface displaced by a float texture). Both read the surface's
// parametrisation at the hit: its tangents along u and v and, for bump mapping, how the
// normal itself turns along them.
#include <vector>

#include "engine/core/math.h"
#include "engine/core/rgb.h"
#include "engine/core/sampler.h"
#include "engine/scene/texture.h"

namespace foton {

// The local parametrisation at a surface point (pbrt's shading geometry).
struct ShadingGeometry {
    Vec3 n{0.f, 0.f, 1.f};                          // the shading normal, unit, outward
    Vec3 dpdu{0.f, 0.f, 0.f}, dpdv{0.f, 0.f, 0.f};  // the shading tangents
    Vec3 dndu{0.f, 0.f, 0.f}, dndv{0.f, 0.f, 0.f};  // 0 where the normal does not turn
};

// dq/du and dq/dv of a quantity q interpolated linearly over a triangle whose corners have
// texture coordinates t0, t1, t2 (positions give dp/du, dp/dv; vertex normals dn/du, dn/dv).
// False, and nothing written, when the corners' uv are degenerate.
bool triangle_partials(const Vec3& q0, const Vec3& q1, const Vec3& q2, Point2 t0, Point2 t1,
                       Point2 t2, Vec3& dqdu, Vec3& dqdv);

// n turned by a normal map's texel: (2 rgb - 1) in the frame of T = dpdu made perpendicular
// to n, B = n x T, n, its x and y times `scale` (glTF's normalTexture.scale). Unchanged when
// dpdu has no part perpendicular to n.
Vec3 normal_mapped(const Vec3& n, const Vec3& dpdu, const RGB& texel, float scale = 1.f);

// pbrt-v4's BumpMap: the normal of p + d(u, v) n, with the displaced tangents
// dpdu + (d(u + du, v) - d) / du n + d dndu (likewise for v) from forward differences of
// step 0.0005 in texture space (pbrt-v4's step without ray differentials), on the side of n.
Vec3 bump_mapped(const ShadingGeometry& g, const Texture& displacement,
                 const std::vector<TextureImage>& images, const TexPoint& at);

}  // namespace foton
