#include "bvh_build.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <utility>

#include "ray1.h"
#include "simd.h"

namespace foton::kern {

namespace {

// Boxes in the build are 4-wide registers (x, y, z, unused): one min and one max extend a box.
using V4 = simd::FloatW<4>;

constexpr uint32_t kMaxBins = 64;
// Past this depth a node is split at the median of its widest centroid axis, which bounds the
// depth (and so the traversal stacks) even for pathological inputs.
constexpr uint32_t kMaxSahDepth = 64;
// Nodes at least this large bin their halves in parallel.
constexpr std::size_t kParallelBinning = 1u << 16;
// Nodes at least this large bin into two sets of bins (Builder::bin_range).
constexpr std::size_t kSplitBinning = 64;

// Lane 3 of a PrimRef half holds the id or padding, whose bits read as a float are mostly
// denormals; arithmetic on denormals takes a slow microcode path on many CPUs (it made the
// build 3x slower), so the lane is zeroed on load.
V4 xyz_mask() {
    alignas(16) const uint32_t bits[4] = {~0u, ~0u, ~0u, 0u};
    return xsimd::bitwise_cast<V4>(xsimd::batch<uint32_t, V4::arch_type>::load_aligned(bits));
}
V4 load_lo(const PrimRef& r) {
    return V4::load_aligned(r.lo) & xyz_mask();
}
V4 load_hi(const PrimRef& r) {
    return V4::load_aligned(r.hi) & xyz_mask();
}

float half_area(const V4& lo, const V4& hi) {
    alignas(16) float e[4];
    (hi - lo).store_aligned(e);
    if (!(e[0] >= 0.f)) return 0.f;  // an empty box
    return e[0] * e[1] + e[1] * e[2] + e[2] * e[0];
}
float half_area(const float lo[3], const float hi[3]) {
    const float e0 = hi[0] - lo[0], e1 = hi[1] - lo[1], e2 = hi[2] - lo[2];
    if (!(e0 >= 0.f)) return 0.f;
    return e0 * e1 + e1 * e2 + e2 * e0;
}

// No default member initialisers: arrays of bins must not pay for a constructor.
struct Box {
    V4 lo, hi;
    static Box empty() { return {V4(kInf), V4(-kInf)}; }
    void extend(const V4& l, const V4& h) {
        lo = xsimd::min(lo, l);
        hi = xsimd::max(hi, h);
    }
    void extend(const Box& b) { extend(b.lo, b.hi); }
    void extend_point(const V4& p) { extend(p, p); }
};

// Left uninitialised on purpose: a node clears only the bins it uses (clearing all 64 x 3 for
// every one of the ~n/2 nodes was most of the build time).
struct Bins {
    Box box[3][kMaxBins];
    uint32_t count[3][kMaxBins];
    void clear(uint32_t nb) {
        for (int a = 0; a < 3; ++a)
            for (uint32_t b = 0; b < nb; ++b) {
                box[a][b] = Box::empty();
                count[a][b] = 0;
            }
    }
    void merge(const Bins& o, uint32_t nb) {
        for (int a = 0; a < 3; ++a)
            for (uint32_t b = 0; b < nb; ++b) {
                box[a][b].extend(o.box[a][b]);
                count[a][b] += o.count[a][b];
            }
    }
};

void store_box(const Box& b, BinaryNode& n) {
    alignas(16) float lo[4], hi[4];
    b.lo.store_aligned(lo);
    b.hi.store_aligned(hi);
    for (int a = 0; a < 3; ++a) n.lo[a] = lo[a], n.hi[a] = hi[a];
}

// Centroids are kept doubled (lo + hi) throughout: the same order, one multiply less.
V4 centroid2(const PrimRef& r) {
    return load_lo(r) + load_hi(r);
}

// Partition of [first, last) by centroid: left when (c_a - o) s < split, which is
// int((c_a - o) s) < bin for the non-negative values binning sees, with the same float
// operations, so every primitive goes to the side it was counted on. Returns the first right
// one; accumulates both sides' centroid boxes. Branchless and out of place: each reference is
// written through a pointer chosen by its side, to the front (left) or the back (right) of
// `scratch`, then the range is copied back. The side is a coin toss to the branch predictor,
// and an in-place Hoare partition mispredicted about half of them (a third of the build's
// samples sat there). A free function with locals so the compiler keeps everything in
// registers.
PrimRef* partition(PrimRef* first, PrimRef* last, PrimRef* scratch, int a, float o, float s,
                   float split, Box& left_c, Box& right_c) {
    const V4 mask = xyz_mask();
    V4 llo(kInf), lhi(-kInf), rlo(kInf), rhi(-kInf);
    PrimRef* l = scratch;
    PrimRef* r = scratch + (last - first);
    for (PrimRef* it = first; it < last; ++it) {
        const PrimRef x = *it;
        const bool left = (x.lo[a] + x.hi[a] - o) * s < split;
        r -= !left;
        *(left ? l : r) = x;
        l += left;
        const V4 c = (V4::load_aligned(x.lo) & mask) + (V4::load_aligned(x.hi) & mask);
        const auto is_left = xsimd::batch_bool<float, V4::arch_type>(left);
        llo = xsimd::select(is_left, xsimd::min(llo, c), llo);
        lhi = xsimd::select(is_left, xsimd::max(lhi, c), lhi);
        rlo = xsimd::select(is_left, rlo, xsimd::min(rlo, c));
        rhi = xsimd::select(is_left, rhi, xsimd::max(rhi, c));
    }
    std::copy(scratch, scratch + (last - first), first);
    left_c = {llo, lhi};
    right_c = {rlo, rhi};
    return first + (l - scratch);
}

struct Binner {
    V4 origin, scale;
    uint32_t bins;
    // Bin of a doubled centroid along each axis. No clamp needed: the centroid lies in the
    // centroid box and scale = bins (1 - 1e-6) / extent keeps the product below `bins` (an
    // axis of zero extent has scale 0, bin 0). Lane 3 is garbage and unused.
    void index(const V4& c2, int32_t out[4]) const {
        xsimd::batch_cast<int32_t>((c2 - origin) * scale).store_aligned(out);
    }
};

struct Builder {
    PrimRef* refs;
    PrimRef* scratch;  // as large as refs; a node partitions through its own range of it
    BinaryNode* nodes;
    std::atomic<uint32_t>* next_node;
    const BvhBuildParams& p;

    uint32_t block_shift;  // leaf_block = 1 << block_shift
    float blocks(std::size_t n) const {
        return float((n + (std::size_t(1) << block_shift) - 1) >> block_shift);
    }

    void bin_range(const Binner& bn, std::size_t begin, std::size_t end, Bins& out) const {
        if (p.parallel && end - begin >= kParallelBinning) {
            const std::size_t mid = begin + (end - begin) / 2;
            Bins right;
            right.clear(bn.bins);
            p.parallel([&] { bin_range(bn, begin, mid, out); },
                       [&] { bin_range(bn, mid, end, right); });
            out.merge(right, bn.bins);
            return;
        }
        // Neighbouring primitives (close in space after partitioning) often fall into the
        // same bin, and each extends that bin's box in memory, so the read-modify-writes
        // chain through store forwarding. Even and odd primitives go to two bin sets, merged
        // after: half the chain, and the same bins (min, max and counts do not care about
        // order).
        if (end - begin < kSplitBinning) {
            for (std::size_t i = begin; i < end; ++i) add(bn, refs[i], out);
            return;
        }
        Bins odd;
        odd.clear(bn.bins);
        std::size_t i = begin;
        for (; i + 1 < end; i += 2) {
            add(bn, refs[i], out);
            add(bn, refs[i + 1], odd);
        }
        if (i < end) add(bn, refs[i], out);
        out.merge(odd, bn.bins);
    }

    static void add(const Binner& bn, const PrimRef& r, Bins& out) {
        const V4 lo = load_lo(r), hi = load_hi(r);
        alignas(16) int32_t b[4];
        bn.index(lo + hi, b);
        for (int a = 0; a < 3; ++a) {
            out.box[a][b[a]].extend(lo, hi);
            ++out.count[a][b[a]];
        }
    }

    void make_leaf(uint32_t slot, std::size_t begin, std::size_t end, const Box& box) const {
        BinaryNode& n = nodes[slot];
        store_box(box, n);
        n.first = uint32_t(begin);
        n.count = uint32_t(end - begin);
    }

    // Returns the depth of the subtree built in slot `slot` over refs[begin, end).
    uint32_t build(uint32_t slot, std::size_t begin, std::size_t end, const Box& box,
                   const Box& cbox, uint32_t depth) const {
        const std::size_t n = end - begin;
        // A node that fits one block is a leaf: a split cannot beat one block test.
        if (n <= (std::size_t(1) << block_shift) || n == 1) {
            make_leaf(slot, begin, end, box);
            return 1;
        }
        alignas(16) float clo[4], chi[4];
        cbox.lo.store_aligned(clo);
        cbox.hi.store_aligned(chi);
        float ext[3];
        for (int a = 0; a < 3; ++a) ext[a] = chi[a] - clo[a];
        const bool flat = ext[0] <= 0.f && ext[1] <= 0.f && ext[2] <= 0.f;

        // Best binned SAH split.
        int best_axis = -1;
        uint32_t best_bin = 0;
        float best_cost = std::numeric_limits<float>::infinity();
        const float leaf_cost = blocks(n);
        const float area = half_area(box.lo, box.hi);
        Binner bn;
        Bins bins;
        uint32_t nb = 0;
        alignas(16) float sc[4] = {0, 0, 0, 0};
        if (!flat && depth < kMaxSahDepth) {
            // Small nodes need fewer bins: a node's fixed cost (clearing and sweeping the
            // bins) would otherwise dwarf binning its few primitives. 4 + n / 20 bins (the rule
            // Embree's binned builder uses) instead of min(n, 32) cut the dragon's binary
            // build from ~255 to ~207 ms, and the SAH came out lower on all four bench meshes
            // (dragon 48.8 -> 46.8).
            nb =
                std::clamp<uint32_t>(std::min<uint32_t>(p.bins, uint32_t(4 + n / 20)), 2, kMaxBins);
            for (int a = 0; a < 3; ++a)
                sc[a] = ext[a] > 0.f ? float(nb) * (1.f - 1e-6f) / ext[a] : 0.f;
            bn = Binner{cbox.lo, V4::load_aligned(sc), nb};
            bins.clear(nb);
            bin_range(bn, begin, end, bins);
            for (int a = 0; a < 3; ++a) {
                if (ext[a] <= 0.f) continue;
                // Right-to-left sweep: cost of the right side for each plane.
                float right_cost[kMaxBins];
                Box acc = Box::empty();
                uint32_t cnt = 0;
                for (uint32_t b = nb - 1; b > 0; --b) {
                    acc.extend(bins.box[a][b]);
                    cnt += bins.count[a][b];
                    right_cost[b] = cnt ? half_area(acc.lo, acc.hi) * blocks(cnt) : 0.f;
                }
                Box lacc = Box::empty();
                uint32_t lcnt = 0;
                for (uint32_t b = 1; b < nb; ++b) {
                    lacc.extend(bins.box[a][b - 1]);
                    lcnt += bins.count[a][b - 1];
                    if (lcnt == 0 || lcnt == n) continue;
                    const float c = half_area(lacc.lo, lacc.hi) * blocks(lcnt) + right_cost[b];
                    if (c < best_cost) {
                        best_cost = c;
                        best_axis = a;
                        best_bin = b;
                    }
                }
            }
            if (best_axis >= 0)
                best_cost = p.traversal_cost + (area > 0.f ? best_cost / area : 0.f);
        }
        if (n <= p.max_leaf && leaf_cost <= best_cost) {
            make_leaf(slot, begin, end, box);
            return 1;
        }

        // Partition. The children's boxes are the unions of their bins' boxes; their centroid
        // boxes come out of the partition pass.
        Box lbox = Box::empty(), lcbox = Box::empty(), rbox = Box::empty(), rcbox = Box::empty();
        std::size_t mid;
        if (best_axis >= 0) {
            for (uint32_t b = 0; b < nb; ++b)
                (b < best_bin ? lbox : rbox).extend(bins.box[best_axis][b]);
            mid = std::size_t(partition(refs + begin, refs + end, scratch + begin, best_axis,
                                        clo[best_axis], sc[best_axis], float(best_bin), lcbox,
                                        rcbox) -
                              refs);
        } else {
            // No usable plane (all centroids equal, or too deep): split at the median of the
            // widest centroid axis, which always makes progress.
            int axis = 0;
            for (int a = 1; a < 3; ++a)
                if (ext[a] > ext[axis]) axis = a;
            mid = begin + n / 2;
            if (!flat)
                std::nth_element(refs + begin, refs + mid, refs + end,
                                 [axis](const PrimRef& x, const PrimRef& y) {
                                     return x.lo[axis] + x.hi[axis] < y.lo[axis] + y.hi[axis];
                                 });
            for (std::size_t k = begin; k < end; ++k) {
                Box& b = k < mid ? lbox : rbox;
                Box& c = k < mid ? lcbox : rcbox;
                b.extend(load_lo(refs[k]), load_hi(refs[k]));
                c.extend_point(centroid2(refs[k]));
            }
        }

        BinaryNode& node = nodes[slot];
        store_box(box, node);
        node.count = 0;
        node.left = next_node->fetch_add(2, std::memory_order_relaxed);
        node.right = node.left + 1;
        uint32_t dl = 0, dr = 0;
        auto left = [&] { dl = build(node.left, begin, mid, lbox, lcbox, depth + 1); };
        auto right = [&] { dr = build(node.right, mid, end, rbox, rcbox, depth + 1); };
        if (p.parallel && n >= p.parallel_grain) {
            p.parallel(left, right);
        } else {
            left();
            right();
        }
        return 1 + std::max(dl, dr);
    }
};

}  // namespace

BinaryBvh build_binary_bvh(std::vector<PrimRef>& refs, const BvhBuildParams& params) {
    BinaryBvh out;
    if (refs.empty()) return out;
    out.nodes = std::make_unique_for_overwrite<BinaryNode[]>(2 * refs.size() - 1);
    std::atomic<uint32_t> next_node{1};
    Box box = Box::empty(), cbox = Box::empty();
    for (const PrimRef& r : refs) {
        box.extend(load_lo(r), load_hi(r));
        cbox.extend_point(centroid2(r));
    }
    uint32_t shift = 0;
    while ((2u << shift) <= std::max<uint32_t>(1, params.leaf_block)) ++shift;
    // Uninitialised, like the nodes: only the partitions write it, and each reads what it wrote.
    const auto scratch = std::make_unique_for_overwrite<PrimRef[]>(refs.size());
    Builder b{refs.data(), scratch.get(), out.nodes.get(), &next_node, params, shift};
    out.depth = b.build(0, 0, refs.size(), box, cbox, 0);
    out.used = next_node.load();
    out.prims.resize(refs.size());
    for (std::size_t i = 0; i < refs.size(); ++i) out.prims[i] = refs[i].id;
    return out;
}

double sah_cost(const BinaryBvh& bvh, float traversal_cost, float primitive_cost) {
    if (bvh.empty()) return 0.0;
    const double root = half_area(bvh.nodes[0].lo, bvh.nodes[0].hi);
    double cost = 0.0;
    // Walk from the root: unused slots are not part of the tree.
    std::vector<uint32_t> stack{0};
    while (!stack.empty()) {
        const BinaryNode& n = bvh.nodes[stack.back()];
        stack.pop_back();
        const double a = half_area(n.lo, n.hi);
        if (n.leaf()) {
            cost += a * primitive_cost * n.count;
        } else {
            cost += a * traversal_cost;
            stack.push_back(n.left);
            stack.push_back(n.right);
        }
    }
    return root > 0.0 ? cost / root : cost;
}

namespace {

struct Collapser {
    const BinaryBvh& bvh;
    uint32_t width;
    WideTree& out;

    WideChild child_of(uint32_t b) const {
        const BinaryNode& n = bvh.nodes[b];
        WideChild c;
        for (int a = 0; a < 3; ++a) c.lo[a] = n.lo[a], c.hi[a] = n.hi[a];
        c.leaf = n.leaf();
        c.index = n.leaf() ? n.first : b;  // inner: the binary index until it is collapsed
        c.count = n.count;
        return c;
    }

    // Emits the wide node for binary node `b`; returns its index and (via depth) its height.
    uint32_t collapse(uint32_t b, uint32_t& depth) {
        std::vector<WideChild> kids;
        const BinaryNode& n = bvh.nodes[b];
        if (n.leaf()) {
            kids.push_back(child_of(b));
        } else {
            kids.push_back(child_of(n.left));
            kids.push_back(child_of(n.right));
        }
        while (kids.size() < width) {
            int open = -1;
            float best = -1.f;
            for (std::size_t i = 0; i < kids.size(); ++i) {
                if (kids[i].leaf) continue;
                const float a = half_area(kids[i].lo, kids[i].hi);
                if (a > best) best = a, open = int(i);
            }
            if (open < 0) break;
            const BinaryNode& o = bvh.nodes[kids[open].index];
            kids[open] = child_of(o.left);
            kids.insert(kids.begin() + open + 1, child_of(o.right));
        }
        const uint32_t w = uint32_t(out.nodes.size());
        out.nodes.emplace_back();
        uint32_t sub = 0;
        for (WideChild& k : kids) {
            if (k.leaf) continue;
            uint32_t d = 0;
            k.index = collapse(k.index, d);
            sub = std::max(sub, d);
        }
        depth = 1 + sub;
        out.nodes[w] = std::move(kids);
        return w;
    }
};

}  // namespace

WideTree collapse_bvh(const BinaryBvh& bvh, uint32_t width) {
    WideTree out;
    out.width = std::max<uint32_t>(2, width);
    if (bvh.empty()) return out;
    Collapser c{bvh, out.width, out};
    c.collapse(0, out.depth);
    return out;
}

double sah_cost(const WideTree& tree, float traversal_cost, float primitive_cost) {
    if (tree.nodes.empty()) return 0.0;
    auto node_area = [&](const std::vector<WideChild>& kids) {
        float lo[3] = {kInf, kInf, kInf}, hi[3] = {-kInf, -kInf, -kInf};
        for (const WideChild& k : kids)
            for (int a = 0; a < 3; ++a)
                lo[a] = std::min(lo[a], k.lo[a]), hi[a] = std::max(hi[a], k.hi[a]);
        return double(half_area(lo, hi));
    };
    const double root = node_area(tree.nodes[0]);
    double cost = 0.0;
    for (const auto& kids : tree.nodes) {
        cost += node_area(kids) * traversal_cost;
        for (const WideChild& k : kids)
            if (k.leaf) cost += double(half_area(k.lo, k.hi)) * primitive_cost * k.count;
    }
    return root > 0.0 ? cost / root : cost;
}

}  // namespace foton::kern
