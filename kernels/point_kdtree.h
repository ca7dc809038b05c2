#pragma once
// Balanced kd-tree over 3D points (photons) in implicit heap layout, with SIMD leaf buckets.
//
// Jensen's photon map stores one photon per node of a left-balanced tree so that node i has
// children 2i and 2i+1 and the array has no holes. Here every leaf is a bucket of kKdBucket
// points instead of one, so that the distance test of a leaf is a few SIMD instructions:
//   * L = ceil(n / kKdBucket) leaves form a complete binary tree in heap order: internal
//     nodes 1 .. L-1 (split value and axis), leaves L .. 2L-1;
//   * the points are kept in tree order (SoA x, y, z and the caller's index), leaf by leaf
//     from left to right; every bucket is full except the rightmost one, which is padded
//     with points at infinity that no query accepts, so leaves need no tail masks;
//   * each split is the median of the node's points along the widest axis of their
//     bounding box (Jensen's rule), placed so that the left subtree holds exactly the
//     points of its leaves.
// Queries: k nearest with a maximum radius (results in max-heap order, farthest first), a
// scalar twin of it for the tests, a batched form with SoA results, and a range query.
#include <cstdint>
#include <functional>
#include <vector>

#include <xsimd/xsimd.hpp>

#include "huge_page_allocator.h"
#include "ray1.h"
#include "simd.h"

namespace foton::kern {

// Points per leaf. 32 beat 16 and 64 at k = 50 .. 500 on 1M dragon photons (AVX-512, see
// bench/bench_point_kdtree.cpp); a multiple of every SIMD width, so leaves need no tail.
inline constexpr std::size_t kKdBucket = 32;
static_assert(kKdBucket % simd::kWidth == 0);

struct KdNode {
    float split;
    uint32_t axis;
};

// Results of a batch of kNN queries, in SoA: query q owns the row index[q * k .. q * k + k)
// (and the same row of dist2), of which the first count[q] entries are valid.
struct KnnBatchResult {
    uint32_t k = 0;
    std::vector<uint32_t> index;
    std::vector<float> dist2;
    std::vector<uint32_t> count;
    void resize(std::size_t queries, uint32_t k_) {
        k = k_;
        index.resize(queries * k_);
        dist2.resize(queries * k_);
        count.resize(queries);
    }
};

class PointKdTree {
  public:
    // Runs two jobs, possibly in parallel (the engine passes tbb::parallel_invoke); an empty
    // function runs them one after the other. Kernels do not depend on TBB.
    using ParallelInvoke =
        std::function<void(const std::function<void()>&, const std::function<void()>&)>;

    // Builds over points (x[i], y[i], z[i]), i < n. Queries report i.
    void build(const float* x, const float* y, const float* z, std::size_t n,
               const ParallelInvoke& parallel = {});

    std::size_t size() const { return n_; }
    bool empty() const { return n_ == 0; }
    std::size_t memory_bytes() const;

    // The (up to) k points nearest to q with squared distance < max_d2, written to
    // out_index / out_d2 (room for k) in max-heap order: out_d2[0] is the largest.
    uint32_t knn(const float q[3], float max_d2, uint32_t k, uint32_t* out_index,
                 float* out_d2) const;
    // Scalar twin of knn: same traversal, scalar leaf test; identical results.
    uint32_t knn_scalar(const float q[3], float max_d2, uint32_t k, uint32_t* out_index,
                        float* out_d2) const;
    // n queries (qx, qy, qz, max_d2 arrays) into SoA rows of `out` (resized to n x k).
    void knn_batch(const float* qx, const float* qy, const float* qz, const float* max_d2,
                   std::size_t n, uint32_t k, KnnBatchResult& out) const;

    // Calls f(index, d2) for every point with d2 < r2, in tree order.
    template <class F>
    void for_each_in_radius(const float q[3], float r2, F&& f) const;
    // Range query into vectors (cleared first); returns the count.
    std::size_t radius(const float q[3], float r2, std::vector<uint32_t>& index,
                       std::vector<float>& d2) const;

    // Tree order: slot s holds the caller's point order()[s] (kInvalidId for padding).
    const std::vector<uint32_t>& order() const { return index_; }

  private:
    template <bool Simd>
    uint32_t knn_impl(const float q[3], float max_d2, uint32_t k, uint32_t* out_index,
                      float* out_d2) const;
    template <class Leaf>
    void traverse(const float q[3], const float& bound, Leaf&& leaf) const;
    template <class F>
    void scan_leaf(uint32_t slot, const float q[3], const float& bound, F&& f) const;

    // In-order position of leaf h (L <= h < 2L): the deepest level holds the leftmost leaves.
    uint32_t leaf_position(uint32_t h) const {
        return h >= first_deep_ ? h - first_deep_ : (2 * leaves_ - first_deep_) + (h - leaves_);
    }

    std::size_t n_ = 0;
    uint32_t leaves_ = 0, first_deep_ = 0;
    // On 2 MB pages where the system allows (huge_page_allocator.h): kNN walks them at random.
    std::vector<KdNode, HugePageAllocator<KdNode>> nodes_;  // [1, leaves_) used
    std::vector<float, HugePageAllocator<float>> x_, y_, z_;
    std::vector<uint32_t> index_;
};

// The indices of points (x[i], y[i], z[i]), i < n, in Morton (Z-curve) order of their
// positions in their bounding box: neighbours in the order are neighbours in space.
std::vector<uint32_t> morton_order(const float* x, const float* y, const float* z, std::size_t n);

// Sorts a knn() result (a max-heap of `count` entries) by ascending distance, in place.
void sort_knn_result(uint32_t count, uint32_t* index, float* d2);

// ---------------------------------------------------------------------------------------
// Traversal, shared by every query. Descends to the nearer child first and pushes the
// farther one with the Arya–Mount incremental lower bound on its squared distance; `bound`
// is read each time, so a kNN search prunes harder as its heap fills.
template <class Leaf>
inline void PointKdTree::traverse(const float q[3], const float& bound, Leaf&& leaf) const {
    if (n_ == 0) return;
    struct Entry {
        uint32_t node;
        float rd;
        float off[3];
    };
    Entry stack[64];
    int top = 0;
    Entry cur{1, 0.f, {0.f, 0.f, 0.f}};
    for (;;) {
        while (cur.node < leaves_) {
            const KdNode nd = nodes_[cur.node];
            const float diff = q[nd.axis] - nd.split;
            const uint32_t near = 2 * cur.node + (diff >= 0.f ? 1u : 0u);
            Entry far = cur;
            far.node = near ^ 1u;
            far.rd = cur.rd - cur.off[nd.axis] * cur.off[nd.axis] + diff * diff;
            far.off[nd.axis] = diff;
            stack[top++] = far;
            cur.node = near;
        }
        leaf(leaf_position(cur.node) * uint32_t(kKdBucket));
        do {
            if (top == 0) return;
            cur = stack[--top];
        } while (!(cur.rd < bound));
    }
}

// The SIMD distance test of one leaf bucket: f(index, d2) for each point with d2 < bound.
// `bound` is re-read per accepted lane, since f may lower it (a filling kNN heap).
template <class F>
inline void PointKdTree::scan_leaf(uint32_t slot, const float q[3], const float& bound,
                                   F&& f) const {
    using simd::FloatV;
    const FloatV qx(q[0]), qy(q[1]), qz(q[2]);
    for (std::size_t b = 0; b < kKdBucket; b += simd::kWidth) {
        const std::size_t s = slot + b;
        const FloatV dx = FloatV::load_aligned(&x_[s]) - qx;
        const FloatV dy = FloatV::load_aligned(&y_[s]) - qy;
        const FloatV dz = FloatV::load_aligned(&z_[s]) - qz;
        const FloatV d2 = dx * dx + dy * dy + dz * dz;
        uint32_t bits = simd::movemask(d2 < FloatV(bound));
        if (!bits) continue;
        alignas(64) float lane_d2[simd::kWidth];
        d2.store_aligned(lane_d2);
        while (bits) {
            const int i = __builtin_ctz(bits);
            bits &= bits - 1;
            if (lane_d2[i] < bound) f(index_[s + i], lane_d2[i]);
        }
    }
}

template <class F>
inline void PointKdTree::for_each_in_radius(const float q[3], float r2, F&& f) const {
    traverse(q, r2, [&](uint32_t slot) { scan_leaf(slot, q, r2, f); });
}

}  // namespace foton::kern
