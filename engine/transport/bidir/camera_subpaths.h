#pragma once
// The camera half of an iteration: one camera subpath per pixel, traced as a wavefront. At
// each vertex it gathers every strategy that ends there: the light found by the ray (s = 0),
// a light sample (s = 1), connections to the vertices of the pixel's own light path (s >= 2)
// and merges with the vertices of all light paths within the radius, each with its MIS
// weight (vcm_mis.h). The connections' shadow rays of a bounce are tested as one batch. At
// vertices on the materials the diffuse kernel takes, the BSDF values and densities the
// connections and merges need are queued and evaluated as one batch of lobe pairs
// (common/lobe_pairs.h) after the bounce's hits.
#include <cstdint>
#include <vector>

#include "engine/core/ray_batch.h"
#include "engine/core/stats.h"
#include "engine/transport/common/lobe_pairs.h"
#include "engine/transport/common/surface.h"
#include "engine/transport/common/wavefront.h"
#include "kernels/point_kdtree.h"
#include "light_vertices.h"
#include "vcm_context.h"
#include "vertex_grid.h"

namespace foton {

// A bounce's camera vertex whose joins wait for the lobe-pair kernel: its state before the
// continuation changes it.
struct QueuedVertex {
    uint32_t slot;
    int t;    // camera vertices of a strategy ending here
    float q;  // its continuation probability
    RGB beta;
    SubpathMis m;
    SurfacePoint sp;
};
// A connection to light vertex j: the camera side's lobe pair `pair`, the light side's
// pair + 1.
struct QueuedConnection {
    uint32_t vertex, j, pair;
    float dist2, cos_c, cos_l, cos_shading;
};
struct QueuedMerge {
    uint32_t vertex, j, pair;
};

struct CameraSubpathWorkspace : WavefrontBuffers {
    std::vector<SubpathMis> mis;
    std::vector<Vec3> p_prev;
    std::vector<uint8_t> specular;  // every vertex so far was sampled from a delta lobe
    std::vector<uint32_t> path;     // the pixel's light path: its index in the full image
    // The bounce's joins through the lobe-pair kernel (kern::eval_lobes).
    LobePairs pairs;
    std::vector<QueuedVertex> vertices;
    std::vector<QueuedConnection> connections;
    std::vector<QueuedMerge> merges;
    std::vector<uint32_t> shadow_layer;  // each shadow ray's strategy layer (strategy_images)
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
        if (!use_kdtree) return grid.query(p, visit);
        const float q[3] = {p.x, p.y, p.z};
        kdtree.for_each_in_radius(q, radius * radius, [&](uint32_t i, float) { visit(i); });
    }
};

// Traces the camera subpaths of film pixels [first, first + count) (row-major) and writes
// each pixel's estimate of this iteration to `radiance` (count entries), and with
// c.layers enabled and `layers` given, what each strategy added (c.layers.count() entries
// per pixel) to `layers`.
void trace_camera_subpaths(const VcmContext& c, const LightPathStore& store, uint32_t first,
                           uint32_t count, CameraSubpathWorkspace& ws, std::vector<RGB>& radiance,
                           std::vector<RGB>* layers, RenderStats& stats);

}  // namespace foton
