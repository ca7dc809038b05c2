#include "mesh_tree_accel.h"

#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <functional>
#include <type_traits>

#include "engine/core/thread_pinning.h"
#include "object_box.h"

namespace foton {

namespace {
void add_counts(TraceCounters& c, const kern::TreeCounters& oc) {
    c.cells += oc.nodes;
    c.triangle_tests += oc.blocks * kern::kBlockWidth;
}
}  // namespace

template <class Tree, AccelType kType>
MeshTreeAccel<Tree, kType>::MeshTreeAccel(const Scene& scene, int threads)
    : scene_(scene), instances_(scene, kType, threads) {
    trees_.resize(scene.meshes.size());
    std::vector<kern::PrimRef> refs;
    auto build_meshes = [&] {
        for (uint32_t g = 0; g < scene.objects.size(); ++g) {
            const Object& o = scene.objects[g];
            if (o.instance >= 0) continue;             // in the instance layer
            if (!traced_by_backend(o.kind)) continue;  // the wrappers'
            if (o.kind == ObjectKind::Mesh) {
                const TriangleMesh& m = scene.meshes[o.index];
                if constexpr (std::is_same_v<Tree, kern::TriangleKdTree>) {
                    kern::KdTreeParams p;  // the upper levels' subtrees built in parallel
                    p.parallel = [](const std::function<void()>& a,
                                    const std::function<void()>& b) { tbb::parallel_invoke(a, b); };
                    trees_[o.index].build(m.positions.data(), m.indices.data(), m.num_triangles(),
                                          p);
                } else {
                    trees_[o.index].build(m.positions.data(), m.indices.data(), m.num_triangles());
                }
            }
            refs.push_back(padded_object_ref(scene, g));
        }
    };
    // Within --threads, as the bvh's build (the tree is the same for any count).
    if (threads > 0) {
        PinnedArena arena(threads);
        arena.execute(build_meshes);
    } else {
        build_meshes();
    }
    kern::BvhBuildParams bp;
    bp.leaf_block = 1;
    bp.max_leaf = 2;
    objects_ = kern::build_binary_bvh(refs, bp);
}

template <class Tree, AccelType kType>
std::size_t MeshTreeAccel<Tree, kType>::memory_bytes() const {
    std::size_t n = objects_.used * sizeof(kern::BinaryNode) +
                    objects_.prims.size() * sizeof(uint32_t) + instances_.memory_bytes();
    for (const Tree& t : trees_) n += t.memory_bytes();
    return n;
}

template <class Tree, AccelType kType>
bool MeshTreeAccel<Tree, kType>::closest(const kern::Ray1& ray, Hit1& hit, TraceCounters& c) const {
    hit.t = std::min(hit.t, ray.tmax);
    const Vec3 org{ray.ox, ray.oy, ray.oz}, dir{ray.dx, ray.dy, ray.dz};
    kern::walk_binary_bvh(
        objects_, ray, [&] { return hit.geom == kNoHit ? hit.t : hit.t * kern::kBvhCullScale; },
        [&](uint32_t g) {
            const Object& o = scene_.objects[g];
            if (o.kind == ObjectKind::Sphere) {
                float t;
                ++c.sphere_tests;
                if (intersect_sphere(scene_.spheres[o.index], org, dir, ray.tmin, hit.t, t))
                    hit = Hit1{t, 0.f, 0.f, 0, g};
                return false;
            }
            kern::TriHit th;
            th.t = hit.t;
            kern::TreeCounters oc;
            if (trees_[o.index].intersect(ray, th, &oc)) hit = Hit1{th.t, th.u, th.v, th.id, g};
            add_counts(c, oc);
            return false;
        });
    if (!instances_.empty()) instances_.closest(ray, hit, c);
    return hit.geom != kNoHit;
}

template <class Tree, AccelType kType>
bool MeshTreeAccel<Tree, kType>::any(const kern::Ray1& ray, TraceCounters& c) const {
    const Vec3 org{ray.ox, ray.oy, ray.oz}, dir{ray.dx, ray.dy, ray.dz};
    bool hit = false;
    kern::walk_binary_bvh(
        objects_, ray, [&] { return ray.tmax; },
        [&](uint32_t g) {
            const Object& o = scene_.objects[g];
            if (o.kind == ObjectKind::Sphere) {
                float t;
                ++c.sphere_tests;
                hit = intersect_sphere(scene_.spheres[o.index], org, dir, ray.tmin, ray.tmax, t);
                return hit;
            }
            kern::TreeCounters oc;
            hit = trees_[o.index].occluded(ray, &oc);
            add_counts(c, oc);
            return hit;
        });
    return hit || (!instances_.empty() && instances_.any(ray, c));
}

template class MeshTreeAccel<kern::TriangleOctree, AccelType::Octree>;
template class MeshTreeAccel<kern::TriangleKdTree, AccelType::KdTree>;

}  // namespace foton
