#include "shape_intersector.h"

#include <algorithm>

#include "object_box.h"

namespace foton {

ShapeIntersector::ShapeIntersector(const Scene& scene, std::unique_ptr<Intersector> inner)
    : scene_(scene), inner_(std::move(inner)) {
    std::vector<kern::PrimRef> refs;
    for (uint32_t g = 0; g < scene.objects.size(); ++g) {
        if (scene.objects[g].kind != ObjectKind::Shape) continue;
        // An empty box (a CSG intersection of disjoint solids) holds nothing to hit.
        if (scene.object_bounds(g).empty()) continue;
        refs.push_back(padded_object_ref(scene, g));
    }
    kern::BvhBuildParams p;
    p.leaf_block = 1;
    p.max_leaf = 2;
    bvh_ = kern::build_binary_bvh(refs, p);
}

std::size_t ShapeIntersector::memory_bytes() const {
    return inner_->memory_bytes() + bvh_.used * sizeof(kern::BinaryNode) +
           bvh_.prims.size() * sizeof(uint32_t);
}

bool ShapeIntersector::closest_shape(const kern::Ray1& ray, Hit1& hit, TraceCounters& c) const {
    const Vec3 org{ray.ox, ray.oy, ray.oz}, dir{ray.dx, ray.dy, ray.dz};
    bool found = false;
    kern::walk_binary_bvh(
        bvh_, ray, [&] { return std::min(hit.t, ray.tmax); },
        [&](uint32_t g) {
            ++c.shape_tests;
            float t;
            uint32_t prim;
            if (scene_.shapes[scene_.objects[g].index].closest(
                    org, dir, ray.tmin, std::min(hit.t, ray.tmax), t, prim)) {
                hit = Hit1{t, 0.f, 0.f, prim, g};
                found = true;
            }
            return false;
        });
    return found;
}

bool ShapeIntersector::any_shape(const kern::Ray1& ray, TraceCounters& c) const {
    const Vec3 org{ray.ox, ray.oy, ray.oz}, dir{ray.dx, ray.dy, ray.dz};
    bool hit = false;
    kern::walk_binary_bvh(
        bvh_, ray, [&] { return ray.tmax; },
        [&](uint32_t g) {
            ++c.shape_tests;
            hit = scene_.shapes[scene_.objects[g].index].any(org, dir, ray.tmin, ray.tmax);
            return hit;
        });
    return hit;
}

void ShapeIntersector::intersect(const RayBatch& rays, HitBatch& hits, TraceCounters& c) const {
    inner_->intersect(rays, hits, c);
    for (std::size_t i = 0; i < rays.size(); ++i) {
        Hit1 h{hits.t[i], hits.u[i], hits.v[i], hits.prim[i], hits.geom[i]};
        if (h.geom == kNoHit) h.t = kInfinity;
        if (!closest_shape(ray_at(rays, i), h, c)) continue;
        hits.t[i] = h.t;
        hits.u[i] = h.u;
        hits.v[i] = h.v;
        hits.prim[i] = h.prim;
        hits.geom[i] = h.geom;
    }
}

void ShapeIntersector::occluded(const RayBatch& rays, std::vector<uint8_t>& occ,
                                TraceCounters& c) const {
    inner_->occluded(rays, occ, c);
    for (std::size_t i = 0; i < rays.size(); ++i)
        if (!occ[i]) occ[i] = any_shape(ray_at(rays, i), c) ? 1 : 0;
}

bool ShapeIntersector::intersect1(const kern::Ray1& ray, Hit1& hit, TraceCounters& c) const {
    const bool inner_hit = inner_->intersect1(ray, hit, c);
    if (!inner_hit) hit.t = kInfinity;
    return closest_shape(ray, hit, c) || inner_hit;
}

bool ShapeIntersector::occluded1(const kern::Ray1& ray, TraceCounters& c) const {
    return inner_->occluded1(ray, c) || any_shape(ray, c);
}

}  // namespace foton
