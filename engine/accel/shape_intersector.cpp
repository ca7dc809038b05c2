#include "shape_intersector.h"

#include <algorithm>

#include "object_box.h"

namespace foton {

ShapeIntersector::ShapeIntersector(const Scene& scene, std::unique_ptr<Intersector> inner)
    : LayeredIntersector(std::move(inner)), scene_(scene) {
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

bool ShapeIntersector::closest_own(const kern::Ray1& ray, Hit1& hit, TraceCounters& c) const {
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

bool ShapeIntersector::any_own(const kern::Ray1& ray, TraceCounters& c) const {
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

}  // namespace foton
