#pragma once
// The differential geometry at a hit, derived on demand from a HitBatch entry: position,
// geometric and shading normals (both facing the incoming ray), and the ray offset scale.
#include "engine/core/math.h"
#include "engine/core/ray_batch.h"
#include "engine/scene/scene.h"

namespace foton {

struct SurfacePoint {
    Vec3 p;
    Vec3 ng;          // geometric normal, facing the side the ray came from
    Vec3 ns;          // shading normal (interpolated for smooth meshes), same side as ng
    bool front_face;  // the ray hit the side the geometry's own normal points to
    float epsilon;    // offset for rays leaving the surface, scaled with the coordinates
    Point2 uv;        // texture coordinates (computed only where the material is textured)
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

}  // namespace foton
