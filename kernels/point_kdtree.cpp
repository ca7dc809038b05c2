#include "point_kdtree.h"

#include <algorithm>
#include <utility>
#include <vector>

namespace foton::kern {

namespace {

struct BuildPoint {
    float p[3];
    uint32_t index;
};

// Subtrees smaller than this are built by the calling thread: a task costs more than the
// median search of a few hundred points. Small enough for many tasks: a left-balanced tree's
// two subtrees differ in size (100k points split 65 : 35), and with only a few large tasks
// the larger one held 2 threads to 1.5x.
constexpr std::size_t kParallelGrain = 1u << 12;

struct Builder {
    BuildPoint* pts;
    KdNode* nodes;
    uint32_t leaves, first_deep;
    const PointKdTree::ParallelInvoke* parallel;

    uint32_t position(uint32_t h) const {
        return h >= first_deep ? h - first_deep : (2 * leaves - first_deep) + (h - leaves);
    }
    uint32_t leftmost_leaf(uint32_t h) const {
        while (h < leaves) h = 2 * h;
        return h;
    }

    void build(uint32_t node, std::size_t lo, std::size_t hi) const {
        if (node >= leaves) return;
        float bmin[3] = {kInf, kInf, kInf}, bmax[3] = {-kInf, -kInf, -kInf};
        for (std::size_t i = lo; i < hi; ++i)
            for (int a = 0; a < 3; ++a) {
                bmin[a] = std::min(bmin[a], pts[i].p[a]);
                bmax[a] = std::max(bmax[a], pts[i].p[a]);
            }
        uint32_t axis = 0;
        for (uint32_t a = 1; a < 3; ++a)
            if (bmax[a] - bmin[a] > bmax[axis] - bmin[axis]) axis = a;
        // The right subtree starts at the first point of its leftmost leaf.
        const std::size_t mid = std::size_t(position(leftmost_leaf(2 * node + 1))) * kKdBucket;
        std::nth_element(
            pts + lo, pts + mid, pts + hi,
            [axis](const BuildPoint& a, const BuildPoint& b) { return a.p[axis] < b.p[axis]; });
        nodes[node] = KdNode{pts[mid].p[axis], axis};
        auto left = [&] { build(2 * node, lo, mid); };
        auto right = [&] { build(2 * node + 1, mid, hi); };
        if (*parallel && hi - lo > kParallelGrain) {
            (*parallel)(left, right);
        } else {
            left();
            right();
        }
    }
};

// Max-heap of (d2, index) pairs living in the caller's output arrays. Until it holds k
// entries it is an unordered array and the search bound is the query's max radius; from
// then on the bound is the heap's largest distance.
struct KnnHeap {
    float* d2;
    uint32_t* index;
    uint32_t k, count = 0;
    float bound;

    void sift_down(uint32_t i) {
        const float d = d2[i];
        const uint32_t id = index[i];
        for (;;) {
            uint32_t c = 2 * i + 1;
            if (c >= count) break;
            if (c + 1 < count && d2[c + 1] > d2[c]) ++c;
            if (!(d2[c] > d)) break;
            d2[i] = d2[c];
            index[i] = index[c];
            i = c;
        }
        d2[i] = d;
        index[i] = id;
    }
    // Precondition: d < bound.
    void push(float d, uint32_t id) {
        if (count < k) {
            d2[count] = d;
            index[count] = id;
            if (++count == k) {
                for (uint32_t i = k / 2; i-- > 0;) sift_down(i);
                bound = d2[0];
            }
            return;
        }
        d2[0] = d;
        index[0] = id;
        sift_down(0);
        bound = d2[0];
    }
    // Heap order also for a partial result, so callers always get the farthest first.
    uint32_t finish() {
        if (count < k)
            for (uint32_t i = count / 2; i-- > 0;) sift_down(i);
        return count;
    }
};

}  // namespace

void PointKdTree::build(const float* x, const float* y, const float* z, std::size_t n,
                        const ParallelInvoke& parallel) {
    n_ = n;
    leaves_ = uint32_t((n + kKdBucket - 1) / kKdBucket);
    first_deep_ = 0;
    nodes_.clear();
    x_.clear();
    y_.clear();
    z_.clear();
    index_.clear();
    if (n == 0) return;
    first_deep_ = 1;
    while (2 * first_deep_ <= 2 * leaves_ - 1) first_deep_ *= 2;

    std::vector<BuildPoint> pts(n);
    for (std::size_t i = 0; i < n; ++i) pts[i] = BuildPoint{{x[i], y[i], z[i]}, uint32_t(i)};
    nodes_.assign(leaves_, KdNode{0.f, 0});
    const Builder builder{pts.data(), nodes_.data(), leaves_, first_deep_, &parallel};
    builder.build(1, 0, n);

    const std::size_t slots = std::size_t(leaves_) * kKdBucket;
    x_.assign(slots, kInf);
    y_.assign(slots, kInf);
    z_.assign(slots, kInf);
    index_.assign(slots, kInvalidId);
    for (std::size_t s = 0; s < n; ++s) {
        x_[s] = pts[s].p[0];
        y_[s] = pts[s].p[1];
        z_[s] = pts[s].p[2];
        index_[s] = pts[s].index;
    }
}

std::size_t PointKdTree::memory_bytes() const {
    return nodes_.size() * sizeof(KdNode) + 3 * x_.size() * sizeof(float) +
           index_.size() * sizeof(uint32_t);
}

template <bool Simd>
uint32_t PointKdTree::knn_impl(const float q[3], float max_d2, uint32_t k, uint32_t* out_index,
                               float* out_d2) const {
    if (k == 0 || n_ == 0) return 0;
    KnnHeap heap{out_d2, out_index, k, 0, max_d2};
    if constexpr (Simd) {
        traverse(q, heap.bound, [&](uint32_t slot) {
            scan_leaf(slot, q, heap.bound, [&](uint32_t id, float d2) { heap.push(d2, id); });
        });
    } else {
        traverse(q, heap.bound, [&](uint32_t slot) {
            for (std::size_t s = slot; s < slot + kKdBucket; ++s) {
                const float dx = x_[s] - q[0], dy = y_[s] - q[1], dz = z_[s] - q[2];
                const float d2 = dx * dx + dy * dy + dz * dz;
                if (d2 < heap.bound) heap.push(d2, index_[s]);
            }
        });
    }
    return heap.finish();
}

uint32_t PointKdTree::knn(const float q[3], float max_d2, uint32_t k, uint32_t* out_index,
                          float* out_d2) const {
    return knn_impl<true>(q, max_d2, k, out_index, out_d2);
}

uint32_t PointKdTree::knn_scalar(const float q[3], float max_d2, uint32_t k, uint32_t* out_index,
                                 float* out_d2) const {
    return knn_impl<false>(q, max_d2, k, out_index, out_d2);
}

std::vector<uint32_t> morton_order(const float* x, const float* y, const float* z, std::size_t n) {
    float lo[3] = {kInf, kInf, kInf}, hi[3] = {-kInf, -kInf, -kInf};
    const float* p[3] = {x, y, z};
    for (std::size_t i = 0; i < n; ++i)
        for (int a = 0; a < 3; ++a) {
            if (p[a][i] < lo[a]) lo[a] = p[a][i];
            if (p[a][i] > hi[a]) hi[a] = p[a][i];
        }
    auto spread = [](uint64_t v) {  // 21 bits to every third bit of 63
        v &= 0x1fffff;
        v = (v | v << 32) & 0x1f00000000ffffull;
        v = (v | v << 16) & 0x1f0000ff0000ffull;
        v = (v | v << 8) & 0x100f00f00f00f00full;
        v = (v | v << 4) & 0x10c30c30c30c30c3ull;
        v = (v | v << 2) & 0x1249249249249249ull;
        return v;
    };
    std::vector<std::pair<uint64_t, uint32_t>> keyed(n);
    for (std::size_t i = 0; i < n; ++i) {
        uint64_t code = 0;
        for (int a = 0; a < 3; ++a) {
            const float extent = hi[a] - lo[a];
            const float t = extent > 0.f ? (p[a][i] - lo[a]) / extent : 0.f;
            // NaN and out-of-range coordinates clamp to the box: they only affect the order.
            const float c = t > 0.f ? std::min(t, 1.f) * 2097151.f : 0.f;
            code |= spread(uint64_t(c)) << a;
        }
        keyed[i] = {code, uint32_t(i)};
    }
    std::sort(keyed.begin(), keyed.end());
    std::vector<uint32_t> order(n);
    for (std::size_t i = 0; i < n; ++i) order[i] = keyed[i].second;
    return order;
}

void PointKdTree::knn_batch(const float* qx, const float* qy, const float* qz, const float* max_d2,
                            std::size_t n, uint32_t k, KnnBatchResult& out) const {
    out.resize(n, k);
    // The queries run in Morton order of their positions: neighbours in that order walk the
    // same nodes and leaves, which are then still in cache. Each result goes to its query's
    // own row, so the order changes the speed and nothing else.
    for (const uint32_t i : morton_order(qx, qy, qz, n)) {
        const float q[3] = {qx[i], qy[i], qz[i]};
        out.count[i] = knn_impl<true>(q, max_d2[i], k, out.index.data() + std::size_t(i) * k,
                                      out.dist2.data() + std::size_t(i) * k);
    }
}

std::size_t PointKdTree::radius(const float q[3], float r2, std::vector<uint32_t>& index,
                                std::vector<float>& d2) const {
    index.clear();
    d2.clear();
    for_each_in_radius(q, r2, [&](uint32_t i, float d) {
        index.push_back(i);
        d2.push_back(d);
    });
    return index.size();
}

void sort_knn_result(uint32_t count, uint32_t* index, float* d2) {
    // Heap sort: knn() leaves a max-heap, so moving the root to the end repeatedly sorts.
    KnnHeap heap{d2, index, count, count, 0.f};
    while (heap.count > 1) {
        --heap.count;
        std::swap(d2[0], d2[heap.count]);
        std::swap(index[0], index[heap.count]);
        heap.sift_down(0);
    }
}

}  // namespace foton::kern
