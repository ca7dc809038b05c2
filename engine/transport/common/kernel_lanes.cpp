// The hit's part of a kernel lane (kernel_lanes.h): the geometry the kernels rebuild the
// surface from, or a surface made here.
#include "kernel_lanes.h"

namespace foton {

bool put_hit(KernelLanes& L, std::size_t lane, const Scene& scene, const RayBatch& rays,
             const HitBatch& hits, std::size_t i) {
    const Object& obj = scene.objects[hits.geom[i]];
    // Instances, normal- or bump-mapped surfaces and anisotropic ones (their tangent) are made
    // by surface_at.
    const Material& mat = scene.materials[obj.material];
    if (obj.instance >= 0 || !traced_by_backend(obj.kind) || mat.perturbs_normal() ||
        mat.needs_tangent())
        return false;
    float kind;
    if (obj.kind == ObjectKind::Mesh) {
        const TriangleMesh& m = scene.meshes[obj.index];
        const uint32_t* ix = &m.indices[3 * std::size_t(hits.prim[i])];
        L.put3(kern::kDvA0x, lane, m.vertex(ix[0]));
        L.put3(kern::kDvA1x, lane, m.vertex(ix[1]));
        L.put3(kern::kDvA2x, lane, m.vertex(ix[2]));
        kind = 1.f;
        if (obj.smooth) {
            L.put3(kern::kDvN0x, lane, m.vertex_normal(ix[0]));
            L.put3(kern::kDvN1x, lane, m.vertex_normal(ix[1]));
            L.put3(kern::kDvN2x, lane, m.vertex_normal(ix[2]));
            kind = 2.f;
        }
    } else {
        const Sphere& sph = scene.spheres[obj.index];
        L.put3(kern::kDvA0x, lane, sph.center);
        L.col(kern::kDvA1x)[lane] = sph.radius;
        L.put3(kern::kDvOx, lane, rays.origin(i));
        kind = 3.f;
    }
    L.col(kern::kDvSurface)[lane] = kind;
    L.col(kern::kDvT)[lane] = hits.t[i];
    L.col(kern::kDvU)[lane] = hits.u[i];
    L.col(kern::kDvV)[lane] = hits.v[i];
    return true;
}

void put_surface(KernelLanes& L, std::size_t lane, const SurfacePoint& sp) {
    L.col(kern::kDvSurface)[lane] = 0.f;
    L.put3(kern::kDvPx, lane, sp.p);
    L.put3(kern::kDvNgx, lane, sp.ng);
    L.put3(kern::kDvNsx, lane, sp.ns);
    L.col(kern::kDvEps)[lane] = sp.epsilon;
    L.col(kern::kDvFront)[lane] = sp.front_face ? 1.f : 0.f;
}

}  // namespace foton
