// Walking the kd-tree: front to back, far children on a stack with their parameter range.
#include <algorithm>
#include <cmath>

#include "tree_leaves.h"
#include "triangle_kdtree.h"

namespace foton::kern {

template <class Leaf, class Cull>
bool TriangleKdTree::traverse(const Ray1& r, Cull&& cull, Leaf&& leaf, uint64_t& visited) const {
    if (nodes_.empty()) return false;
    // A direction component too small for its reciprocal counts as none: the ray would reach
    // a plane only astronomically far away, and an infinite reciprocal gives 0 x inf = NaN.
    const float o[3] = {r.ox, r.oy, r.oz};
    float d[3] = {r.dx, r.dy, r.dz}, inv[3];
    float t0 = r.tmin, t1 = std::min(r.tmax, cull());
    for (int a = 0; a < 3; ++a) {
        if (std::fabs(d[a]) < kNoDirection) d[a] = 0.f;
        inv[a] = 1.f / d[a];
        if (d[a] == 0.f) {
            if (!(lo_[a] <= o[a] && o[a] <= hi_[a])) return false;
            continue;
        }
        float ta = (lo_[a] - o[a]) * inv[a], tb = (hi_[a] - o[a]) * inv[a];
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
    }
    if (!(t0 <= t1)) return false;

    struct Todo {
        uint32_t node;
        float t0, t1;
    };
    Todo stack[KdTreeParams::kMaxDepth + 4];
    int top = 0;
    uint32_t node = 0;
    for (;;) {
        ++visited;
        const Node* n = &nodes_[node];
        while (!n->leaf()) {
            const int a = n->axis();
            const float split = n->split();
            const uint32_t below = node + 1, above = n->index();
            if (d[a] == 0.f) {
                // Parallel to the plane: the side the ray lies on, or both when it lies in it
                // (a triangle touching the plane from either side can be hit there).
                if (o[a] == split) stack[top++] = {above, t0, t1};
                node = o[a] <= split ? below : above;
            } else {
                const float tplane = (split - o[a]) * inv[a];
                const bool below_first = o[a] < split || (o[a] == split && d[a] < 0.f);
                const uint32_t first = below_first ? below : above;
                const uint32_t second = below_first ? above : below;
                if (tplane > t1 || tplane <= 0.f) {
                    node = first;
                } else if (tplane < t0) {
                    node = second;
                } else {
                    stack[top++] = {second, tplane, t1};
                    node = first;
                    t1 = tplane;
                }
            }
            ++visited;
            n = &nodes_[node];
        }
        if (n->count() != 0 && leaf(n->index(), n->count(), t1)) return true;
        // The next range still worth entering: none past the closest hit.
        do {
            if (top == 0) return false;
            const Todo& next = stack[--top];
            node = next.node, t0 = next.t0, t1 = std::min(next.t1, cull());
        } while (t0 > t1);
    }
}

bool TriangleKdTree::intersect(const Ray1& r, TriHit& hit, TreeCounters* counters) const {
    return closest_in_leaves(
        r, blocks_.data(), hit, counters,
        [&](auto&& cull, auto&& leaf, uint64_t& n) { return traverse(r, cull, leaf, n); });
}

bool TriangleKdTree::occluded(const Ray1& r, TreeCounters* counters) const {
    return any_in_leaves(r, blocks_.data(), counters, [&](auto&& cull, auto&& leaf, uint64_t& n) {
        return traverse(r, cull, leaf, n);
    });
}

}  // namespace foton::kern
