#include "alpha_intersector.h"
#include "brute_accel.h"
#include "bvh_accel.h"
#include "curve_intersector.h"
#include "embree_accel.h"
#include "grid_accel.h"
#include "mesh_tree_accel.h"
#include "shape_intersector.h"

namespace foton {

namespace {

std::unique_ptr<Intersector> make_backend(const Scene& scene, AccelType type, int threads) {
    switch (type) {
        case AccelType::Brute:
            return std::make_unique<BruteAccel>(scene, false);
        case AccelType::BruteSimd:
            return std::make_unique<BruteAccel>(scene, true);
        case AccelType::Grid: {
            kern::GridParams params;
            params.cells_per_triangle = scene.grid_density;
            return std::make_unique<GridAccel>(scene, params);
        }
        case AccelType::Bvh:
            return std::make_unique<BvhAccel>(scene, threads);
        case AccelType::Embree:
            return std::make_unique<EmbreeAccel>(scene, threads);
        case AccelType::Octree:
            return std::make_unique<OctreeAccel>(scene, threads);
        case AccelType::KdTree:
            return std::make_unique<KdTreeAccel>(scene, threads);
    }
    return nullptr;
}

}  // namespace

std::unique_ptr<Intersector> make_intersector(const Scene& scene, AccelType type, int threads) {
    std::unique_ptr<Intersector> backend = make_backend(scene, type, threads);
    for (const Object& o : scene.objects)
        if (traced_by_backend(o.kind) && scene.materials[o.material].cuts_out()) {
            backend = std::make_unique<AlphaIntersector>(scene, std::move(backend));
            break;
        }
    // Curves (never cut out: the importers refuse alpha on them) above the cut-outs.
    if (scene.has_curves()) backend = std::make_unique<CurveIntersector>(scene, std::move(backend));
    // Analytic shapes and CSG trees (never cut out either) on top.
    if (!scene.shapes.empty())
        backend = std::make_unique<ShapeIntersector>(scene, std::move(backend));
    return backend;
}

}  // namespace foton
