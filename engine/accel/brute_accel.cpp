#include "brute_accel.h"

#include <numeric>

#include "kernels/moller_trumbore.h"

namespace foton {

BruteAccel::BruteAccel(const Scene& scene, bool simd)
    : scene_(scene),
      simd_(simd),
      instances_(scene, simd ? AccelType::BruteSimd : AccelType::Brute, 0) {
    for (uint32_t g = 0; g < scene.objects.size(); ++g) {
        const Object& o = scene.objects[g];
        if (o.instance >= 0) continue;             // in the instance layer
        if (!traced_by_backend(o.kind)) continue;  // the wrappers'
        if (o.kind == ObjectKind::Sphere) {
            sphere_objects_.push_back(g);
            continue;
        }
        const TriangleMesh& m = scene.meshes[o.index];
        std::vector<uint32_t> tris(m.num_triangles());
        std::iota(tris.begin(), tris.end(), 0u);
        MeshBlocks mb{g, {}};
        kern::pack_triangle_blocks(m.positions.data(), m.indices.data(), tris.data(), tris.size(),
                                   mb.blocks);
        meshes_.push_back(std::move(mb));
    }
}

std::size_t BruteAccel::memory_bytes() const {
    std::size_t n = instances_.memory_bytes();
    for (const auto& m : meshes_) n += m.blocks.size() * sizeof(kern::TriangleBlock);
    return n;
}

bool BruteAccel::closest(const kern::Ray1& ray, Hit1& hit, TraceCounters& c) const {
    kern::TriHit th;
    th.t = ray.tmax;
    for (const MeshBlocks& m : meshes_) {
        bool improved = false;
        if (simd_) {
            for (const kern::TriangleBlock& b : m.blocks)
                improved |= kern::intersect_block(ray, b, th);
        } else {
            for (const kern::TriangleBlock& b : m.blocks)
                improved |= kern::intersect_block_scalar(ray, b, th);
        }
        c.triangle_tests += m.blocks.size() * kern::kBlockWidth;
        if (improved) {
            hit.t = th.t;
            hit.u = th.u;
            hit.v = th.v;
            hit.prim = th.id;
            hit.geom = m.geom;
        }
    }
    const Vec3 o{ray.ox, ray.oy, ray.oz}, d{ray.dx, ray.dy, ray.dz};
    for (uint32_t g : sphere_objects_) {
        float t;
        ++c.sphere_tests;
        if (intersect_sphere(scene_.spheres[scene_.objects[g].index], o, d, ray.tmin, th.t, t)) {
            th.t = t;
            hit = Hit1{t, 0.f, 0.f, 0, g};
        }
    }
    if (!instances_.empty()) {
        hit.t = th.t;
        instances_.closest(ray, hit, c);
    }
    return hit.geom != kNoHit;
}

bool BruteAccel::any(const kern::Ray1& ray, TraceCounters& c) const {
    for (const MeshBlocks& m : meshes_) {
        for (const kern::TriangleBlock& b : m.blocks) {
            c.triangle_tests += kern::kBlockWidth;
            if (simd_ ? kern::occluded_block(ray, b) : kern::occluded_block_scalar(ray, b))
                return true;
        }
    }
    const Vec3 o{ray.ox, ray.oy, ray.oz}, d{ray.dx, ray.dy, ray.dz};
    for (uint32_t g : sphere_objects_) {
        float t;
        ++c.sphere_tests;
        if (intersect_sphere(scene_.spheres[scene_.objects[g].index], o, d, ray.tmin, ray.tmax, t))
            return true;
    }
    return !instances_.empty() && instances_.any(ray, c);
}

}  // namespace foton
