#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "triangle_bvh.h"

namespace foton::kern {

namespace {

struct Box3 {
    float lo[3] = {kInf, kInf, kInf}, hi[3] = {-kInf, -kInf, -kInf};
    void extend(const float* p) {
        for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], p[a]), hi[a] = std::max(hi[a], p[a]);
    }
    void extend(const Box3& b) {
        extend(b.lo);
        extend(b.hi);
    }
    bool empty() const { return !(lo[0] <= hi[0]); }
};

// The box of a triangle that can be hit, or false: as the build, a triangle with a
// non-finite corner or zero area is never hit (Möller–Trumbore's det is 0 or NaN for it).
bool triangle_box(const float* const p[3], Box3& box) {
    for (int k = 0; k < 3; ++k)
        if (!std::isfinite(p[k][0]) || !std::isfinite(p[k][1]) || !std::isfinite(p[k][2]))
            return false;
    const float e1[3] = {p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]};
    const float e2[3] = {p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]};
    if (e1[1] * e2[2] - e1[2] * e2[1] == 0.f && e1[2] * e2[0] - e1[0] * e2[2] == 0.f &&
        e1[0] * e2[1] - e1[1] * e2[0] == 0.f)
        return false;
    for (int k = 0; k < 3; ++k) box.extend(p[k]);
    return true;
}

}  // namespace

template <std::size_t N, std::size_t M>
void TriangleBvhT<N, M>::refit(const TriangleSource* sources, std::size_t num_sources) {
    const SourceIds ids(sources, num_sources);
    const std::size_t built = stats_.triangles + stats_.skipped;
    if (ids.total() != built)
        throw std::invalid_argument("BVH refit: the sources hold " + std::to_string(ids.total()) +
                                    " triangles, the tree was built over " + std::to_string(built));
    if (root_ == kBvhEmpty) return;

    // Leaves: every lane re-packed from its triangle's new corners; the leaf's box is that of
    // the triangles that can be hit. A lane that cannot be hit is made inert (zero edges), and
    // keeps its id, so that a later refit can bring it back.
    auto leaf_box = [&](uint32_t ref) {
        Box3 box;
        for (uint32_t k = 0; k < bvh_leaf_blocks(ref); ++k) {
            Block& b = blocks_[bvh_leaf_first(ref) + k];
            for (std::size_t lane = 0; lane < M; ++lane) {
                const uint32_t id = b.id[lane];
                if (id == kInvalidId) continue;
                const float* p[3];
                ids.corners(id, p);
                if (triangle_box(p, box)) {
                    b.set(lane, p[0], p[1], p[2], id);
                } else {
                    const float zero[3] = {0.f, 0.f, 0.f};
                    b.set(lane, zero, zero, zero, id);
                }
            }
        }
        return box;
    };
    // Boxes bottom up. The collapse emits a node before its subtrees, so every child has a
    // larger index than its parent, and one pass from the last node to the root sees each
    // child's box before its parent's. Boxes are kept unpadded, then padded once per child
    // slot, as the build does.
    std::vector<Box3> box(nodes_.size());
    for (std::size_t w = nodes_.size(); w-- > 0;) {
        Node& n = nodes_[w];
        for (std::size_t c = 0; c < N; ++c) {
            const uint32_t ref = n.child[c];
            if (ref == 0) continue;  // an empty slot (no inner child is the root)
            const Box3 b = bvh_is_leaf(ref) ? leaf_box(ref) : box[ref];
            box[w].extend(b);
            float lo[3] = {kInf, kInf, kInf}, hi[3] = {-kInf, -kInf, -kInf};
            if (!b.empty()) {
                std::copy(b.lo, b.lo + 3, lo);
                std::copy(b.hi, b.hi + 3, hi);
                pad_box(lo, hi);
            }
            for (int a = 0; a < 3; ++a) {
                n.bounds[2 * a][c] = lo[a];
                n.bounds[2 * a + 1][c] = hi[a];
            }
        }
    }
    if (!box[0].empty()) {
        std::copy(box[0].lo, box[0].lo + 3, bounds_lo_);
        std::copy(box[0].hi, box[0].hi + 3, bounds_hi_);
        const float d[3] = {bounds_hi_[0] - bounds_lo_[0], bounds_hi_[1] - bounds_lo_[1],
                            bounds_hi_[2] - bounds_lo_[2]};
        packet_span_ =
            std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) * bvh_detail::kPacketOriginSpan;
    }

    // The scalar twin: its corners by id, and its binary tree's boxes, bottom up the same way
    // (a binary node's children are allocated after it).
    if (twin_.empty()) return;
    for (uint32_t id = 0; id < built; ++id) {
        const float* p[3];
        ids.corners(id, p);
        for (int k = 0; k < 3; ++k)
            for (int a = 0; a < 3; ++a) twin_tri_[9 * std::size_t(id) + 3 * k + a] = p[k][a];
    }
    std::vector<Box3> tbox(twin_.used);
    for (std::size_t i = twin_.used; i-- > 0;) {
        BinaryNode& n = twin_.nodes[i];
        if (n.leaf()) {
            for (uint32_t j = n.first; j < n.first + n.count; ++j) {
                const float* t = &twin_tri_[9 * std::size_t(twin_.prims[j])];
                const float* p[3] = {t, t + 3, t + 6};
                triangle_box(p, tbox[i]);
            }
        } else {
            tbox[i].extend(tbox[n.left]);
            tbox[i].extend(tbox[n.right]);
        }
        float lo[3] = {kInf, kInf, kInf}, hi[3] = {-kInf, -kInf, -kInf};
        if (!tbox[i].empty()) {
            std::copy(tbox[i].lo, tbox[i].lo + 3, lo);
            std::copy(tbox[i].hi, tbox[i].hi + 3, hi);
            pad_box(lo, hi);
        }
        std::copy(lo, lo + 3, n.lo);
        std::copy(hi, hi + 3, n.hi);
    }
}

// The shapes triangle_bvh.cpp instantiates.
template void TriangleBvhT<4, 4>::refit(const TriangleSource*, std::size_t);
#if defined(__AVX__)
template void TriangleBvhT<8, 4>::refit(const TriangleSource*, std::size_t);
template void TriangleBvhT<8, 8>::refit(const TriangleSource*, std::size_t);
#endif
#if defined(__AVX512BW__)
template void TriangleBvhT<16, 4>::refit(const TriangleSource*, std::size_t);
template void TriangleBvhT<16, 8>::refit(const TriangleSource*, std::size_t);
#endif

}  // namespace foton::kern
