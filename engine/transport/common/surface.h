#pragma once
// The differential geometry at a hit, derived on demand from a HitBatch entry: position,
// geometric and shading normals (both facing the incoming ray), and the ray offset scale;
// the shadow rays that leave it.
#include <cmath>

#include "engine/core/math.h"
#include "engine/core/ray_batch.h"
#include "engine/core/warp.h"
#include "engine/scene/light_set.h"
#include "engine/scene/scene.h"

namespace foton {

struct SurfacePoint {
    Vec3 p;
    Vec3 ng;          // geometric normal, facing the side the ray came from
    Vec3 ns;          // shading normal (interpolated for smooth meshes), same side as ng
    bool front_face;  // the ray hit the side the geometry's own normal points to
    float epsilon;    // offset for rays leaving the surface, scaled with the coordinates
    Point2 uv;        // texture coordinates (computed only where the material is textured)
    // The width in uv of a pixel's footprint here, seen from the camera (textured meshes and
    // spheres; 0 elsewhere): what MIP-mapped textures pick their level by; and the uv steps of
    // one pixel along the image's x and y (the footprint's ellipse, for EWA).
    float footprint = 0.f;
    Point2 duvdx{0.f, 0.f}, duvdy{0.f, 0.f};
    // The shading tangent: dp/du made perpendicular to ns, unit, where the material's BSDF
    // is anisotropic (Material::needs_tangent); zero elsewhere.
    Vec3 ss{0.f, 0.f, 0.f};
    // The mesh's vertex colour here (materials that read it; white elsewhere).
    RGB vertex_color{1.f};
    // The mesh's second uv set here when it has one and the material is textured; else uv.
    Point2 uv2{0.f, 0.f};
    // The BSDF's frame: around ns, its x axis along ss when there is one.
    warp::Frame frame() const { return warp::Frame(ns, ss); }
    // Where its textures read themselves (uv, and the point and normal for textures mapped
    // by position or mixed by direction).
    TexPoint tex() const {
        TexPoint t{uv, p, ng};
        t.footprint = footprint;
        t.duvdx = duvdx;
        t.duvdy = duvdy;
        t.vertex_color = vertex_color;
        t.uv2 = uv2;
        return t;
    }
};

SurfacePoint surface_at(const Scene& scene, uint32_t geom, uint32_t prim, float t, float u, float v,
                        const Vec3& origin, const Vec3& dir);

// The surface that entry i of a traced batch hit (hits.geom[i] != kNoHit).
inline SurfacePoint surface_at(const Scene& scene, const RayBatch& rays, const HitBatch& hits,
                               std::size_t i) {
    return surface_at(scene, hits.geom[i], hits.prim[i], hits.t[i], hits.u[i], hits.v[i],
                      rays.origin(i), rays.direction(i));
}

// Origin for a ray leaving `sp` in direction `w`: pushed off the surface along the
// geometric normal, to the side `w` goes.
inline Vec3 offset_origin(const SurfacePoint& sp, const Vec3& w) {
    return dot(w, sp.ng) >= 0.f ? sp.p + sp.ng * sp.epsilon : sp.p - sp.ng * sp.epsilon;
}

// A shadow ray: visible when nothing lies on it before tmax.
struct ShadowRay {
    Vec3 origin, dir;
    float tmax;
};

// The shadow ray from `sp` to point q on another surface (normal nq, either orientation;
// zero for a point on no surface: a point light, the camera), offset by eps_q there. Both
// ends are pushed off their surfaces to the side the other end lies on, and the ray joins the
// pushed ends. Then neither surface can block it by rounding: a convex emitter lies behind
// its tangent plane at q, and the segment in front of it. Stopping short along the unpushed
// direction does not do: near a sphere light's silhouette the origin's offset alone moves
// where the ray enters the sphere by about sqrt(2 r offset), far more than any margin (a
// quarter of the direct light under a sphere was lost so).
inline ShadowRay shadow_ray_to(const SurfacePoint& sp, const Vec3& q, const Vec3& nq, float eps_q) {
    const Vec3 o = offset_origin(sp, q - sp.p);
    const Vec3 end = q + (dot(nq, o - q) >= 0.f ? nq : -nq) * eps_q;
    const Vec3 d = end - o;
    const float len = length(d);
    return {o, len > 0.f ? d / len : d, len * (1.f - 1e-4f)};
}

// The same towards a light sample: to its point, or along its direction when the light is
// at infinity (environment, directional).
inline ShadowRay shadow_ray_to(const SurfacePoint& sp, const LightSample& ls) {
    if (std::isinf(ls.dist)) return {offset_origin(sp, ls.wi), ls.wi, kInfinity};
    return shadow_ray_to(sp, ls.p_light, ls.n_light, offset_epsilon(ls.p_light, ls.dist));
}

}  // namespace foton
