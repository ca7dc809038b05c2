#pragma once
// What a camera half of an iteration works with (camera_subpaths.h): its per-path state, the
// bounce's joins queued for the lobe-pair kernel, and the iteration's light vertices with
// their merge index.
#include <cstdint>
#include <vector>

#include "engine/core/ray_batch.h"
#include "engine/transport/common/lobe_pairs.h"
#include "engine/transport/common/surface.h"
#include "engine/transport/common/wavefront.h"
#include "kernels/point_kdtree.h"
#include "light_vertices.h"
#include "subpath_media.h"
#include "vcm_mis.h"
#include "vertex_grid.h"

namespace foton {

// A bounce's camera vertex whose joins wait for the lobe-pair kernel: its state before the
// continuation changes it.
struct QueuedVertex {
    uint32_t slot, geom;
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
    std::vector<uint32_t> length;  // per slot: segments from the camera to its last vertex
    SubpathMedia media;
    JoinRays joins;  // the bounce's light samples and connections
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

}  // namespace foton
