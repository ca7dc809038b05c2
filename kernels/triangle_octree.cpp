#include "triangle_octree.h"

#include "tree_leaves.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace foton::kern {

namespace {
constexpr uint32_t axis_bit(int a) {
    return 4u >> a;
}

// Whether triangle (a, b, c) meets the closed box [lo, hi], by the separating axis theorem
// (Akenine-Möller 2001): no separating plane among the box's faces (the caller's bounding
// box test), the triangle's plane and the nine planes through an edge and a box axis. The box
// is grown by a relative 1e-5 first: a triangle rounding puts just outside must stay in.
bool triangle_meets_box(const float* a, const float* b, const float* c, const float lo[3],
                        const float hi[3]) {
    float h[3], v[3][3];
    for (int k = 0; k < 3; ++k) {
        const float centre = 0.5f * (lo[k] + hi[k]);
        h[k] = 0.5f * (hi[k] - lo[k]);
        h[k] += 1e-5f * (h[k] + std::fabs(centre));
        v[0][k] = a[k] - centre, v[1][k] = b[k] - centre, v[2][k] = c[k] - centre;
    }
    auto separated = [&](const float axis[3]) {
        float pmin = kInf, pmax = -kInf;
        for (int i = 0; i < 3; ++i) {
            const float p = axis[0] * v[i][0] + axis[1] * v[i][1] + axis[2] * v[i][2];
            pmin = std::min(pmin, p), pmax = std::max(pmax, p);
        }
        const float r =
            h[0] * std::fabs(axis[0]) + h[1] * std::fabs(axis[1]) + h[2] * std::fabs(axis[2]);
        return pmin > r || pmax < -r;
    };
    float e[3][3];
    for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k) e[i][k] = v[(i + 1) % 3][k] - v[i][k];
    for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k) {
            // The box's axis k crossed with edge i.
            float axis[3] = {0, 0, 0};
            const int k1 = (k + 1) % 3, k2 = (k + 2) % 3;
            axis[k1] = -e[i][k2];
            axis[k2] = e[i][k1];
            if (separated(axis)) return false;
        }
    const float n[3] = {e[0][1] * e[1][2] - e[0][2] * e[1][1],
                        e[0][2] * e[1][0] - e[0][0] * e[1][2],
                        e[0][0] * e[1][1] - e[0][1] * e[1][0]};
    return !separated(n);
}
}  // namespace

void TriangleOctree::build(const float* positions, const uint32_t* indices,
                           std::size_t num_triangles, const OctreeParams& params) {
    positions_ = positions;
    indices_ = indices;
    params_ = params;
    nodes_.clear();
    blocks_.clear();
    references_ = 0;
    depth_ = 0;
    if (num_triangles == 0) return;
    for (int a = 0; a < 3; ++a) lo_[a] = kInf, hi_[a] = -kInf;
    for (std::size_t k = 0; k < 3 * num_triangles; ++k)
        for (int a = 0; a < 3; ++a) {
            lo_[a] = std::min(lo_[a], positions[3 * indices[k] + a]);
            hi_[a] = std::max(hi_[a], positions[3 * indices[k] + a]);
        }
    std::vector<uint32_t> tris(num_triangles);
    std::iota(tris.begin(), tris.end(), 0u);
    nodes_.emplace_back();
    build_node(0, lo_, hi_, tris, 0);
}

void TriangleOctree::build_node(uint32_t node, const float lo[3], const float hi[3],
                                std::vector<uint32_t>& tris, int depth) {
    depth_ = std::max(depth_, depth);
    auto make_leaf = [&] {
        nodes_[node] = {uint32_t(blocks_.size()),
                        uint32_t((tris.size() + kBlockWidth - 1) / kBlockWidth), true};
        pack_triangle_blocks(positions_, indices_, tris.data(), tris.size(), blocks_);
        references_ += tris.size();
    };
    if (tris.size() <= params_.leaf_triangles || depth >= params_.max_depth) return make_leaf();
    const float mid[3] = {0.5f * (lo[0] + hi[0]), 0.5f * (lo[1] + hi[1]), 0.5f * (lo[2] + hi[2])};
    // Each triangle goes to every child it meets (closed boxes: a triangle touching a mid-plane
    // is in the children on both sides, so a ray in that plane finds it in either).
    std::vector<uint32_t> child[8];
    std::size_t total = 0;
    for (const uint32_t t : tris) {
        float tlo[3], thi[3];
        for (int a = 0; a < 3; ++a) {
            const float v0 = positions_[3 * indices_[3 * t] + a],
                        v1 = positions_[3 * indices_[3 * t + 1] + a],
                        v2 = positions_[3 * indices_[3 * t + 2] + a];
            tlo[a] = std::min({v0, v1, v2});
            thi[a] = std::max({v0, v1, v2});
        }
        for (uint32_t c = 0; c < 8; ++c) {
            bool overlaps = true;
            for (int a = 0; a < 3 && overlaps; ++a) {
                const bool upper = c & axis_bit(a);
                overlaps = upper ? thi[a] >= mid[a] : tlo[a] <= mid[a];
            }
            if (!overlaps) continue;
            float clo[3], chi[3];
            for (int a = 0; a < 3; ++a) {
                const bool upper = c & axis_bit(a);
                clo[a] = upper ? mid[a] : lo[a];
                chi[a] = upper ? hi[a] : mid[a];
            }
            if (triangle_meets_box(positions_ + 3 * indices_[3 * t],
                                   positions_ + 3 * indices_[3 * t + 1],
                                   positions_ + 3 * indices_[3 * t + 2], clo, chi))
                child[c].push_back(t), ++total;
        }
    }
    if (float(total) > params_.max_duplication * float(tris.size())) return make_leaf();
    tris.clear();
    tris.shrink_to_fit();
    const uint32_t first = uint32_t(nodes_.size());
    nodes_.resize(nodes_.size() + 8);
    nodes_[node] = {first, 0, false};
    for (uint32_t c = 0; c < 8; ++c) {
        float clo[3], chi[3];
        for (int a = 0; a < 3; ++a) {
            const bool upper = c & axis_bit(a);
            clo[a] = upper ? mid[a] : lo[a];
            chi[a] = upper ? hi[a] : mid[a];
        }
        build_node(first + c, clo, chi, child[c], depth + 1);
    }
}

std::size_t TriangleOctree::memory_bytes() const {
    return nodes_.size() * sizeof(Node) + blocks_.size() * sizeof(TriangleBlock);
}

template <class Leaf, class Cull>
bool TriangleOctree::walk(uint32_t node, const float t0[3], const float t1[3], const float lo[3],
                          const float hi[3], const Walk& w, Cull&& cull, Leaf&& leaf,
                          uint64_t& visited) const {
    const float enter = std::max({t0[0], t0[1], t0[2]}), exit = std::min({t1[0], t1[1], t1[2]});
    if (enter > exit || exit < w.tmin || enter > cull()) return false;
    ++visited;
    const Node& n = nodes_[node];
    if (n.leaf) return n.blocks != 0 && leaf(n.first, n.blocks, exit);
    const float mid[3] = {0.5f * (lo[0] + hi[0]), 0.5f * (lo[1] + hi[1]), 0.5f * (lo[2] + hi[2])};
    // Where the ray crosses each mid-plane; along an axis it does not move, never, and it
    // stays in the half it lies in (the lower one when it lies in the plane: a triangle it can
    // hit there touches the plane, and so is in both halves).
    float tm[3];
    for (int a = 0; a < 3; ++a)
        tm[a] = w.moves[a] ? 0.5f * (t0[a] + t1[a]) : w.o[a] <= mid[a] ? kInf : -kInf;
    // The first child is the one holding the ray where it starts in this node: past a
    // mid-plane (its parameter below the start) along each axis it is in the upper half.
    const float start = std::max(enter, w.tmin);
    uint32_t c = 0;
    for (int a = 0; a < 3; ++a)
        if (tm[a] < start) c |= axis_bit(a);
    for (;;) {
        float c0[3], c1[3], clo[3], chi[3];
        for (int a = 0; a < 3; ++a) {
            const bool upper = c & axis_bit(a);
            c0[a] = upper ? tm[a] : t0[a];
            c1[a] = upper ? t1[a] : tm[a];
            clo[a] = upper ? mid[a] : lo[a];
            chi[a] = upper ? hi[a] : mid[a];
        }
        if (walk(n.first + (c ^ w.mirror), c0, c1, clo, chi, w, cull, leaf, visited)) return true;
        // On through the child's exit plane (the first of equal ones), or out of this node
        // when that is the upper half already.
        const int a = c1[0] <= c1[1] && c1[0] <= c1[2] ? 0 : c1[1] <= c1[2] ? 1 : 2;
        if (c & axis_bit(a)) return false;
        c |= axis_bit(a);
    }
}

template <class Leaf, class Cull>
bool TriangleOctree::traverse(const Ray1& r, Cull&& cull, Leaf&& leaf, uint64_t& visited) const {
    if (nodes_.empty()) return false;
    // The ray mirrored to non-negative directions within the root box. Along an axis it does
    // not move (a component below kNoDirection) it spans the slab it lies in, or misses.
    const float o[3] = {r.ox, r.oy, r.oz}, d[3] = {r.dx, r.dy, r.dz};
    Walk w;
    w.tmin = r.tmin;
    float t0[3], t1[3];
    for (int a = 0; a < 3; ++a) {
        float oa = o[a], da = d[a];
        if (da < 0.f) {
            oa = lo_[a] + hi_[a] - oa;
            da = -da;
            w.mirror |= axis_bit(a);
        }
        w.o[a] = oa;
        w.moves[a] = da >= kNoDirection;
        if (!w.moves[a]) {
            if (!(lo_[a] <= oa && oa <= hi_[a])) return false;
            t0[a] = -kInf;
            t1[a] = kInf;
            continue;
        }
        const float inv = 1.f / da;
        t0[a] = (lo_[a] - oa) * inv;
        t1[a] = (hi_[a] - oa) * inv;
    }
    return walk(0, t0, t1, lo_, hi_, w, cull, leaf, visited);
}

bool TriangleOctree::intersect(const Ray1& r, TriHit& hit, TreeCounters* counters) const {
    return closest_in_leaves(
        r, blocks_.data(), hit, counters,
        [&](auto&& cull, auto&& leaf, uint64_t& n) { return traverse(r, cull, leaf, n); });
}

bool TriangleOctree::occluded(const Ray1& r, TreeCounters* counters) const {
    return any_in_leaves(r, blocks_.data(), counters, [&](auto&& cull, auto&& leaf, uint64_t& n) {
        return traverse(r, cull, leaf, n);
    });
}

}  // namespace foton::kern
