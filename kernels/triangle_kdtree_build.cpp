// The O(n log n) SAH kd-tree build of Wald and Havran (2006), "On building fast kd-trees for
// ray tracing, and on doing that in O(N log N)", with perfect splits.
#include <algorithm>
#include <cmath>
#include <functional>

#include "triangle_kdtree.h"

namespace foton::kern {

namespace {

// At one position, ends sort before triangles lying in the plane, and those before starts:
// the sweep then counts a triangle ending at p as left of p and one starting there as right.
enum : uint8_t { kEnd = 0, kPlanar = 1, kStart = 2 };

struct Event {
    float pos;
    uint32_t tri;
    uint8_t type;
};
using Events = std::vector<Event>;

bool before(const Event& a, const Event& b) {
    return a.pos < b.pos || (a.pos == b.pos && a.type < b.type);
}

struct Box {
    float lo[3], hi[3];
    float area() const {
        const float dx = hi[0] - lo[0], dy = hi[1] - lo[1], dz = hi[2] - lo[2];
        return 2.f * (dx * dy + dy * dz + dz * dx);
    }
    Box child(int axis, float split, bool upper) const {
        Box b = *this;
        (upper ? b.lo : b.hi)[axis] = split;
        return b;
    }
};

// The bounds of triangle (a, b, c) clipped to `box` (Sutherland-Hodgman against its six
// planes); false when nothing of it is inside. The bounds are clamped to the box: a clipped
// vertex rounded just outside must not put a candidate plane outside the node.
bool clipped_bounds(const float* a, const float* b, const float* c, const Box& box, Box& out) {
    float poly[2][9][3];  // a triangle cut by six planes has at most nine corners
    for (int k = 0; k < 3; ++k) poly[0][0][k] = a[k], poly[0][1][k] = b[k], poly[0][2][k] = c[k];
    int n = 3, cur = 0;
    for (int plane = 0; plane < 6 && n > 0; ++plane) {
        const int axis = plane >> 1;
        const bool upper = plane & 1;
        const float bound = upper ? box.hi[axis] : box.lo[axis];
        auto inside = [&](const float* p) { return upper ? p[axis] <= bound : p[axis] >= bound; };
        const float(*in)[3] = poly[cur];
        float(*out_poly)[3] = poly[cur ^ 1];
        int m = 0;
        for (int i = 0; i < n; ++i) {
            const float* p = in[i];
            const float* q = in[(i + 1) % n];
            const bool pin = inside(p), qin = inside(q);
            if (pin) std::copy(p, p + 3, out_poly[m++]);
            if (pin != qin && m < 9) {
                const float s = (bound - p[axis]) / (q[axis] - p[axis]);
                for (int k = 0; k < 3; ++k) out_poly[m][k] = p[k] + s * (q[k] - p[k]);
                out_poly[m++][axis] = bound;
            }
        }
        n = m;
        cur ^= 1;
    }
    if (n == 0) return false;
    for (int k = 0; k < 3; ++k) {
        out.lo[k] = kInf, out.hi[k] = -kInf;
        for (int i = 0; i < n; ++i) {
            out.lo[k] = std::min(out.lo[k], poly[cur][i][k]);
            out.hi[k] = std::max(out.hi[k], poly[cur][i][k]);
        }
        out.lo[k] = std::clamp(out.lo[k], box.lo[k], box.hi[k]);
        out.hi[k] = std::clamp(out.hi[k], box.lo[k], box.hi[k]);
    }
    return true;
}

void add_events(Events ev[3], uint32_t tri, const Box& b) {
    for (int k = 0; k < 3; ++k) {
        if (b.lo[k] == b.hi[k]) {
            ev[k].push_back({b.lo[k], tri, kPlanar});
        } else {
            ev[k].push_back({b.lo[k], tri, kStart});
            ev[k].push_back({b.hi[k], tri, kEnd});
        }
    }
}

enum class Side : uint8_t { Both, Left, Right };

struct Plane {
    int axis = -1;
    float pos = 0.f;
    bool planar_left = true;  // where the triangles lying in the plane go
    float cost = kInf;
};

}  // namespace

// A subtree's nodes and blocks, indices relative to its own arrays; the upper levels build
// their right subtrees as fragments (in parallel or not) and append them with the indices moved.
struct KdFragment {
    std::vector<TriangleKdTree::Node> nodes;
    std::vector<TriangleBlock, HugePageAllocator<TriangleBlock>> blocks;
    std::size_t references = 0, leaves = 0;
    int depth = 0;
    double sah = 0.0;

    void append(KdFragment&& f) {
        const auto node_offset = uint32_t(nodes.size()), block_offset = uint32_t(blocks.size());
        for (TriangleKdTree::Node n : f.nodes) {
            const uint32_t offset = n.leaf() ? block_offset : node_offset;
            n.bits = ((n.index() + offset) << 2) | (n.bits & 3u);
            nodes.push_back(n);
        }
        blocks.insert(blocks.end(), f.blocks.begin(), f.blocks.end());
        references += f.references;
        leaves += f.leaves;
        depth = std::max(depth, f.depth);
        sah += f.sah;
    }
};

class KdTreeBuilder {
  public:
    KdTreeBuilder(const TriangleKdTree& tree, const KdTreeParams& params, std::size_t n,
                  KdFragment& out)
        : tree_(tree), params_(params), side_(n, Side::Both), out_(out) {
        max_depth_ = params.max_depth > 0
                         ? params.max_depth
                         : int(8.f + 1.3f * std::log2(float(std::max<std::size_t>(n, 1))));
        max_depth_ = std::min(max_depth_, KdTreeParams::kMaxDepth);
    }

    void run(Events ev[3], const Box& root, std::size_t n) {
        root_area_ = std::max(root.area(), 1e-30f);
        build(ev, root, n, 0);
    }

  private:
    KdTreeBuilder(const KdTreeBuilder& parent, KdFragment& out)
        : tree_(parent.tree_),
          params_(parent.params_),
          side_(parent.side_.size(), Side::Both),
          out_(out),
          max_depth_(parent.max_depth_),
          root_area_(parent.root_area_) {}

    float sah(const Box& box, int axis, float pos, std::size_t nl, std::size_t nr) const {
        const float inv_area = 1.f / box.area();
        const float pl = box.child(axis, pos, false).area() * inv_area;
        const float pr = box.child(axis, pos, true).area() * inv_area;
        const float lambda = nl == 0 || nr == 0 ? params_.empty_bonus : 1.f;
        return lambda * (params_.traversal_cost +
                         params_.intersection_cost * (pl * float(nl) + pr * float(nr)));
    }

    // One sweep per axis over the sorted events: at each candidate position the triangles
    // left of, right of and in the plane are known from the counts so far.
    Plane find_plane(const Events ev[3], const Box& box, std::size_t n) const {
        Plane best;
        for (int k = 0; k < 3; ++k) {
            const Events& e = ev[k];
            std::size_t nl = 0, nr = n;
            for (std::size_t i = 0; i < e.size();) {
                const float p = e[i].pos;
                std::size_t ends = 0, planar = 0, starts = 0;
                while (i < e.size() && e[i].pos == p && e[i].type == kEnd) ++ends, ++i;
                while (i < e.size() && e[i].pos == p && e[i].type == kPlanar) ++planar, ++i;
                while (i < e.size() && e[i].pos == p && e[i].type == kStart) ++starts, ++i;
                nr -= planar + ends;
                if (p > box.lo[k] && p < box.hi[k]) {
                    const float left = sah(box, k, p, nl + planar, nr);
                    const float right = sah(box, k, p, nl, nr + planar);
                    const float c = std::min(left, right);
                    if (c < best.cost) best = {k, p, left <= right, c};
                }
                nl += starts + planar;
            }
        }
        return best;
    }

    const float* corner(uint32_t tri, int i) const {
        return tree_.positions_ + 3 * tree_.indices_[3 * tri + i];
    }

    void make_leaf(uint32_t node, const Events ev[3], std::size_t n, float area) {
        std::vector<uint32_t> tris;
        tris.reserve(n);
        for (const Event& e : ev[0])
            if (e.type != kEnd) tris.push_back(e.tri);
        const auto first = uint32_t(out_.blocks.size());
        pack_triangle_blocks(tree_.positions_, tree_.indices_, tris.data(), tris.size(),
                             out_.blocks);
        out_.nodes[node] = {uint32_t(out_.blocks.size()) - first, (first << 2) | 3u};
        out_.references += tris.size();
        ++out_.leaves;
        out_.sah += params_.intersection_cost * double(tris.size()) * area / root_area_;
    }

    // Builds the subtree of the triangles whose (clipped) events are `ev` in `box`; returns
    // its root's index. The events are consumed.
    uint32_t build(Events ev[3], const Box& box, std::size_t n, int depth) {
        const auto node = uint32_t(out_.nodes.size());
        out_.nodes.push_back({});
        out_.depth = std::max(out_.depth, depth);
        const float area = box.area();
        Plane plane;
        if (n > params_.leaf_triangles && depth < max_depth_ && area > 0.f)
            plane = find_plane(ev, box, n);
        if (plane.axis < 0 || plane.cost >= params_.intersection_cost * float(n)) {
            make_leaf(node, ev, n, area);
            return node;
        }
        out_.sah += params_.traversal_cost * double(area) / root_area_;

        // Which side each triangle is on: its events along the split axis say it.
        const int k = plane.axis;
        for (const Event& e : ev[k]) side_[e.tri] = Side::Both;
        for (const Event& e : ev[k]) {
            if (e.type == kEnd && e.pos <= plane.pos) {
                side_[e.tri] = Side::Left;
            } else if (e.type == kStart && e.pos >= plane.pos) {
                side_[e.tri] = Side::Right;
            } else if (e.type == kPlanar) {
                const bool left = e.pos < plane.pos || (e.pos == plane.pos && plane.planar_left);
                side_[e.tri] = left ? Side::Left : Side::Right;
            }
        }
        std::vector<uint32_t> straddling;
        for (const Event& e : ev[k])
            if (e.type == kStart && side_[e.tri] == Side::Both) straddling.push_back(e.tri);

        // The one-sided triangles' events keep their order; the straddling ones' are made
        // anew from their parts in each child, sorted (few), and merged in.
        Events left[3], right[3];
        std::size_t nl = 0, nr = 0;
        for (int j = 0; j < 3; ++j) {
            for (const Event& e : ev[j]) {
                if (side_[e.tri] == Side::Left) left[j].push_back(e);
                if (side_[e.tri] == Side::Right) right[j].push_back(e);
            }
            Events().swap(ev[j]);
        }
        for (const Event& e : left[0]) nl += e.type != kEnd;
        for (const Event& e : right[0]) nr += e.type != kEnd;
        const Box lbox = box.child(k, plane.pos, false), rbox = box.child(k, plane.pos, true);
        Events new_left[3], new_right[3];
        for (const uint32_t t : straddling) {
            Box b;
            if (clipped_bounds(corner(t, 0), corner(t, 1), corner(t, 2), lbox, b))
                add_events(new_left, t, b), ++nl;
            if (clipped_bounds(corner(t, 0), corner(t, 1), corner(t, 2), rbox, b))
                add_events(new_right, t, b), ++nr;
        }
        auto merge_in = [](Events& into, Events& fresh) {
            std::sort(fresh.begin(), fresh.end(), before);
            const auto mid = into.size();
            into.insert(into.end(), fresh.begin(), fresh.end());
            std::inplace_merge(into.begin(), into.begin() + std::ptrdiff_t(mid), into.end(),
                               before);
        };
        for (int j = 0; j < 3; ++j) {
            merge_in(left[j], new_left[j]);
            merge_in(right[j], new_right[j]);
        }
        uint32_t above;
        if (depth < params_.parallel_depth && n >= params_.parallel_grain) {
            // The right subtree as a fragment of its own (with its own side array), built
            // beside the left one when a parallel_invoke is given, appended after it either way.
            KdFragment right_part;
            KdTreeBuilder sub(*this, right_part);
            const std::function<void()> lower = [&] { build(left, lbox, nl, depth + 1); };
            const std::function<void()> upper = [&] { sub.build(right, rbox, nr, depth + 1); };
            if (params_.parallel) {
                params_.parallel(lower, upper);
            } else {
                lower();
                upper();
            }
            above = uint32_t(out_.nodes.size());
            out_.append(std::move(right_part));
        } else {
            build(left, lbox, nl, depth + 1);  // at node + 1
            above = build(right, rbox, nr, depth + 1);
        }
        out_.nodes[node] = {std::bit_cast<uint32_t>(plane.pos), (above << 2) | uint32_t(k)};
        return node;
    }

    const TriangleKdTree& tree_;  // its positions and indices
    const KdTreeParams& params_;
    std::vector<Side> side_;  // by triangle; valid for the node being split only
    KdFragment& out_;
    int max_depth_ = 0;
    float root_area_ = 1.f;
};

void TriangleKdTree::build(const float* positions, const uint32_t* indices,
                           std::size_t num_triangles, const KdTreeParams& params) {
    positions_ = positions;
    indices_ = indices;
    nodes_.clear();
    blocks_.clear();
    references_ = leaves_ = 0;
    depth_ = 0;
    sah_ = 0.0;
    if (num_triangles == 0) return;
    Box root;
    for (int k = 0; k < 3; ++k) root.lo[k] = kInf, root.hi[k] = -kInf;
    Events ev[3];
    for (auto& e : ev) e.reserve(2 * num_triangles);
    for (uint32_t t = 0; t < num_triangles; ++t) {
        Box b;
        for (int k = 0; k < 3; ++k) {
            b.lo[k] = kInf, b.hi[k] = -kInf;
            for (int i = 0; i < 3; ++i) {
                const float x = positions[3 * indices[3 * t + i] + k];
                b.lo[k] = std::min(b.lo[k], x), b.hi[k] = std::max(b.hi[k], x);
            }
            root.lo[k] = std::min(root.lo[k], b.lo[k]);
            root.hi[k] = std::max(root.hi[k], b.hi[k]);
        }
        add_events(ev, t, b);
    }
    for (auto& e : ev) std::sort(e.begin(), e.end(), before);
    for (int k = 0; k < 3; ++k) lo_[k] = root.lo[k], hi_[k] = root.hi[k];
    KdFragment whole;
    KdTreeBuilder(*this, params, num_triangles, whole).run(ev, root, num_triangles);
    nodes_ = std::move(whole.nodes);
    blocks_ = std::move(whole.blocks);
    references_ = whole.references;
    leaves_ = whole.leaves;
    depth_ = whole.depth;
    sah_ = whole.sah;
}

std::size_t TriangleKdTree::memory_bytes() const {
    return nodes_.size() * sizeof(Node) + blocks_.size() * sizeof(TriangleBlock);
}

}  // namespace foton::kern
