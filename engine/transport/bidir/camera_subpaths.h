#pragma once
// The camera half of an iteration: one camera subpath per pixel, traced as a wavefront. At
// each vertex it gathers every strategy that ends there: the light found by the ray (s = 0),
// a light sample (s = 1), connections to the vertices of the pixel's own light path (s >= 2)
// and merges with the vertices of all light paths within the radius, each with its MIS
// weight (vcm_mis.h). The connections' shadow rays of a bounce are tested as one batch.
#include <cstdint>
#include <vector>

#include "engine/core/ray_batch.h"
#include "engine/core/stats.h"
#include "engine/transport/common/wavefront.h"
#include "kernels/point_kdtree.h"
#include "light_vertices.h"
#include "vcm_context.h"
#include "vertex_grid.h"

namespace foton {

struct CameraSubpathWorkspace : WavefrontBuffers {
    std::vector<SubpathMis> mis;
    std::vector<Vec3> p_prev;
    std::vector<uint8_t> specular;  // every vertex so far was sampled from a delta lobe
    std::vector<uint32_t> path;     // the pixel's light path: its index in the full image
};

// The light vertices of the iteration and where each path's begin.
struct LightPathStore {
    LightVertices vertices;
    std::vector<uint32_t> first;  // path k: [first[k], first[k + 1])
    // The merge index: the grid, or the kd-tree kernel (merge_index=kdtree).
    bool use_kdtree = false;
    VertexGrid grid;
    kern::PointKdTree kdtree;
    float radius = 0.f;

    // Calls visit(i) for every light vertex i within the merge radius of p.
    template <class Visit>
    void merge_candidates(const Vec3& p, Visit&& visit) const {
        if (!use_kdtree) return grid.query(vertices, p, visit);
        const float q[3] = {p.x, p.y, p.z};
        kdtree.for_each_in_radius(q, radius * radius, [&](uint32_t i, float) { visit(i); });
    }
};

// Traces the camera subpaths of film pixels [first, first + count) (row-major) and writes
// each pixel's estimate of this iteration to `radiance` (count entries).
void trace_camera_subpaths(const VcmContext& c, const LightPathStore& store, uint32_t first,
                           uint32_t count, CameraSubpathWorkspace& ws, std::vector<RGB>& radiance,
                           RenderStats& stats);

}  // namespace foton
