#include "instance_layer.h"

#include "object_box.h"

#include <algorithm>
#include <cmath>

namespace foton {

kern::Ray1 to_instance_space(const Instance& in, const kern::Ray1& ray) {
    const Vec3 o = in.to_object.point({ray.ox, ray.oy, ray.oz});
    const Vec3 d = in.to_object.vector({ray.dx, ray.dy, ray.dz});
    return {o.x, o.y, o.z, d.x, d.y, d.z, ray.tmin, ray.tmax};
}

InstanceLayer::InstanceLayer(const Scene& scene, AccelType blas_type, int threads)
    : scene_(&scene) {
    if (scene.instances.empty()) return;
    blas_of_mesh_.assign(scene.meshes.size(), UINT32_MAX);
    std::vector<kern::PrimRef> refs;
    for (uint32_t g = 0; g < scene.objects.size(); ++g) {
        const Object& o = scene.objects[g];
        if (o.instance < 0) continue;
        if (blas_of_mesh_[o.index] == UINT32_MAX) {
            auto proto = std::make_unique<Scene>();
            proto->meshes.push_back(scene.meshes[o.index]);
            Object po;
            po.kind = ObjectKind::Mesh;
            proto->objects.push_back(po);
            proto->materials.resize(1);
            proto->grid_density = scene.grid_density;
            proto->grid_lazy = scene.grid_lazy;
            blas_of_mesh_[o.index] = uint32_t(blas_.size());
            blas_.push_back(make_intersector(*proto, blas_type, threads));
            prototypes_.push_back(std::move(proto));
        }
        refs.push_back(padded_object_ref(scene, g));
    }
    kern::BvhBuildParams p;
    p.leaf_block = 1;
    p.max_leaf = 2;
    tlas_ = kern::build_binary_bvh(refs, p);
}

std::size_t InstanceLayer::memory_bytes() const {
    std::size_t n = tlas_.used * sizeof(kern::BinaryNode) + tlas_.prims.size() * sizeof(uint32_t);
    for (const auto& b : blas_) n += b->memory_bytes();
    for (const auto& p : prototypes_) n += p->memory_bytes();
    return n;
}

void InstanceLayer::closest(const kern::Ray1& ray, Hit1& hit, TraceCounters& c) const {
    hit.t = std::min(hit.t, ray.tmax);
    kern::walk_binary_bvh(
        tlas_, ray, [&] { return hit.t; },
        [&](uint32_t g) {
            const Object& o = scene_->objects[g];
            kern::Ray1 local = to_instance_space(scene_->instances[std::size_t(o.instance)], ray);
            local.tmax = hit.t;
            Hit1 h;
            ++c.instance_visits;
            if (blas_[blas_of_mesh_[o.index]]->intersect1(local, h, c) && h.t < hit.t)
                hit = Hit1{h.t, h.u, h.v, h.prim, g};
            return false;
        });
}

bool InstanceLayer::any(const kern::Ray1& ray, TraceCounters& c) const {
    bool found = false;
    kern::walk_binary_bvh(
        tlas_, ray, [&] { return ray.tmax; },
        [&](uint32_t g) {
            const Object& o = scene_->objects[g];
            ++c.instance_visits;
            found = blas_[blas_of_mesh_[o.index]]->occluded1(
                to_instance_space(scene_->instances[std::size_t(o.instance)], ray), c);
            return found;
        });
    return found;
}

}  // namespace foton
