#include "triangle_bvh.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "bvh_pack.h"

namespace foton::kern {

namespace {

bool finite3(const float* p) {
    return std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]);
}

// Zero area in float: the cross product of the edges vanishes (such a triangle has det = 0
// for every ray, so it can never be hit).
bool degenerate(const float* p0, const float* p1, const float* p2) {
    const float e1[3] = {p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]};
    const float e2[3] = {p2[0] - p0[0], p2[1] - p0[1], p2[2] - p0[2]};
    const float c[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                        e1[0] * e2[1] - e1[1] * e2[0]};
    return c[0] == 0.f && c[1] == 0.f && c[2] == 0.f;
}

}  // namespace

template <std::size_t N, std::size_t M>
BvhBuildParams TriangleBvhT<N, M>::default_params() {
    BvhBuildParams p;
    p.leaf_block = uint32_t(M);
    // Leaves of one block. Against leaves of up to two (bench/compare_embree, alternating
    // runs, Zen 5): 4-7 % more diffuse rays/s on the bunny and the dragon, 1-13 % more shadow
    // rays, the stadium within 2 %; 10 % more bytes (still below Embree's) and a 7 % longer
    // build.
    p.max_leaf = uint32_t(M);
    p.bins = 32;
    p.traversal_cost = 1.f;
    return p;
}

template <std::size_t N, std::size_t M>
void TriangleBvhT<N, M>::build(const TriangleSource* sources, std::size_t num_sources,
                               const BvhBuildParams& params, bool keep_twin) {
    nodes_.clear();
    blocks_.clear();
    root_ = kBvhEmpty;
    packet_span_ = 0.f;
    stats_ = {};
    twin_ = {};
    twin_tri_.clear();

    const SourceIds ids(sources, num_sources);
    const std::size_t total = ids.total();
    if (total > std::size_t(0xfffffffe)) throw std::length_error("BVH: too many triangles");
    auto corners = [&](uint32_t id, const float* p[3]) { ids.corners(id, p); };
    std::vector<PrimRef> refs;
    refs.reserve(total);
    for (std::size_t s = 0; s < num_sources; ++s) {
        const TriangleSource& src = sources[s];
        for (std::size_t t = 0; t < src.count; ++t) {
            const float* p[3];
            for (int k = 0; k < 3; ++k)
                p[k] = src.positions + 3 * std::size_t(src.indices[3 * t + k]);
            if (!finite3(p[0]) || !finite3(p[1]) || !finite3(p[2]) ||
                degenerate(p[0], p[1], p[2])) {
                ++stats_.skipped;
                continue;
            }
            PrimRef r;
            for (int a = 0; a < 3; ++a) {
                r.lo[a] = std::min({p[0][a], p[1][a], p[2][a]});
                r.hi[a] = std::max({p[0][a], p[1][a], p[2][a]});
            }
            r.id = uint32_t(ids.first_of(s) + t);
            r.pad = 0;
            refs.push_back(r);
        }
    }
    stats_.triangles = refs.size();
    if (refs.empty()) return;

    BvhBuildParams bp = params;
    bp.max_leaf = std::min<uint32_t>(bp.max_leaf, uint32_t(M * kBvhMaxLeafBlocks));
    BinaryBvh bin = build_binary_bvh(refs, bp);
    stats_.sah_binary = sah_cost(bin);
    const WideTree wide = collapse_bvh(bin, uint32_t(N));
    stats_.sah_wide = sah_cost(wide);
    stats_.depth = wide.depth;

    // Leaves gather their triangles' corners from the meshes, a random walk through the index
    // and vertex arrays that waited on every load (a third of the packing's samples). The
    // packing takes the build's primitive order leaf by leaf (in the wide tree's order, which
    // mostly follows it), so prefetching the indices of the triangle 16 places ahead in that
    // order and the corners of the one 8 ahead (whose indices are in cache by then) overlaps
    // most of those misses.
    auto prefetch_ahead = [&](std::size_t j) {
        if (j + 16 < bin.prims.size()) __builtin_prefetch(ids.indices(bin.prims[j + 16]));
        if (j + 8 < bin.prims.size()) {
            const float* p[3];
            corners(bin.prims[j + 8], p);
            for (int c = 0; c < 3; ++c) __builtin_prefetch(p[c]);
        }
    };
    // Pack: nodes in the wide tree's order, each leaf's triangles into consecutive blocks.
    nodes_.resize(wide.nodes.size());
    std::size_t num_blocks = 0;
    for (const auto& kids : wide.nodes)
        for (const WideChild& k : kids)
            if (k.leaf) num_blocks += (k.count + M - 1) / M;
    blocks_.reserve(num_blocks);
    std::size_t used_lanes = 0;
    pack_wide_nodes<N>(wide, nodes_, [&](const WideChild& k) {
        const uint32_t first = uint32_t(blocks_.size());
        const uint32_t nb = uint32_t((k.count + M - 1) / M);
        if (first + nb > kBvhMaxFirstBlock) throw std::length_error("BVH: too many blocks");
        for (uint32_t b = 0; b < nb; ++b) {
            Block& blk = blocks_.emplace_back();
            blk.clear();
            for (std::size_t lane = 0; lane < M && b * M + lane < k.count; ++lane) {
                const std::size_t j = k.index + b * M + lane;
                prefetch_ahead(j);
                const uint32_t tid = bin.prims[j];
                const float* p[3];
                corners(tid, p);
                blk.set(lane, p[0], p[1], p[2], tid);
                ++used_lanes;
            }
        }
        ++stats_.leaves;
        return bvh_make_leaf(first, nb);
    });
    // A root with one leaf child is entered as that leaf.
    root_ = (wide.nodes[0].size() == 1 && wide.nodes[0][0].leaf) ? nodes_[0].child[0] : 0;
    {
        const BinaryNode& r = bin.nodes[0];
        for (int a = 0; a < 3; ++a) bounds_lo_[a] = r.lo[a], bounds_hi_[a] = r.hi[a];
        const float d[3] = {r.hi[0] - r.lo[0], r.hi[1] - r.lo[1], r.hi[2] - r.lo[2]};
        packet_span_ =
            std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) * bvh_detail::kPacketOriginSpan;
    }
    stats_.nodes = nodes_.size();
    stats_.blocks = blocks_.size();
    stats_.fill = blocks_.empty() ? 0.0 : double(used_lanes) / double(blocks_.size() * M);

    if (keep_twin) {
        // Pad the nodes the tree uses (unused slots are uninitialised).
        std::vector<uint32_t> stack{0};
        while (!stack.empty()) {
            BinaryNode& n = bin.nodes[stack.back()];
            stack.pop_back();
            pad_box(n.lo, n.hi);
            if (!n.leaf()) stack.insert(stack.end(), {n.left, n.right});
        }
        twin_tri_.resize(9 * total);
        for (uint32_t id = 0; id < total; ++id) {
            const float* p[3];
            corners(id, p);
            for (int k = 0; k < 3; ++k)
                for (int a = 0; a < 3; ++a) twin_tri_[9 * std::size_t(id) + 3 * k + a] = p[k][a];
        }
        twin_ = std::move(bin);
    }
}

template <std::size_t N, std::size_t M>
std::size_t TriangleBvhT<N, M>::memory_bytes() const {
    return nodes_.size() * sizeof(Node) + blocks_.size() * sizeof(Block);
}

template <std::size_t N, std::size_t M>
bool TriangleBvhT<N, M>::intersect_scalar(const Ray1& r, TriHit& hit) const {
    if (twin_.empty() || bvh_detail::unusable(r)) return false;
    if (r.tmax < hit.t) hit.t = r.tmax;
    const float o[3] = {r.ox, r.oy, r.oz};
    const float inv[3] = {1.f / r.dx, 1.f / r.dy, 1.f / r.dz};
    bool found = false;
    std::vector<uint32_t> stack{0};
    while (!stack.empty()) {
        const BinaryNode& n = twin_.nodes[stack.back()];
        stack.pop_back();
        float tn;
        const float tcull = hit.valid() ? hit.t * kBvhCullScale : hit.t;
        if (!slab_test_scalar(n.lo, n.hi, o, inv, r.tmin, tcull, tn)) continue;
        if (!n.leaf()) {
            stack.push_back(n.right);
            stack.push_back(n.left);
            continue;
        }
        for (uint32_t i = n.first; i < n.first + n.count; ++i) {
            const uint32_t id = twin_.prims[i];
            const float* p = &twin_tri_[9 * std::size_t(id)];
            const float bound = hit.valid() ? std::nextafter(hit.t, kInf) : hit.t;
            float t, u, v;
            if (!intersect_triangle_scalar(r, p[0], p[1], p[2], p[3] - p[0], p[4] - p[1],
                                           p[5] - p[2], p[6] - p[0], p[7] - p[1], p[8] - p[2],
                                           bound, t, u, v))
                continue;
            if (t < hit.t || (t == hit.t && id < hit.id)) {
                hit = TriHit{t, u, v, id};
                found = true;
            }
        }
    }
    return found;
}

template <std::size_t N, std::size_t M>
bool TriangleBvhT<N, M>::occluded_scalar(const Ray1& r) const {
    if (twin_.empty() || bvh_detail::unusable(r)) return false;
    const float o[3] = {r.ox, r.oy, r.oz};
    const float inv[3] = {1.f / r.dx, 1.f / r.dy, 1.f / r.dz};
    std::vector<uint32_t> stack{0};
    while (!stack.empty()) {
        const BinaryNode& n = twin_.nodes[stack.back()];
        stack.pop_back();
        float tn;
        if (!slab_test_scalar(n.lo, n.hi, o, inv, r.tmin, r.tmax, tn)) continue;
        if (!n.leaf()) {
            stack.push_back(n.right);
            stack.push_back(n.left);
            continue;
        }
        for (uint32_t i = n.first; i < n.first + n.count; ++i) {
            const float* p = &twin_tri_[9 * std::size_t(twin_.prims[i])];
            float t, u, v;
            if (intersect_triangle_scalar(r, p[0], p[1], p[2], p[3] - p[0], p[4] - p[1],
                                          p[5] - p[2], p[6] - p[0], p[7] - p[1], p[8] - p[2],
                                          r.tmax, t, u, v))
                return true;
        }
    }
    return false;
}

// The shapes the engine and the benchmarks use.
template class TriangleBvhT<4, 4>;
#if defined(__AVX__)
template class TriangleBvhT<8, 4>;
template class TriangleBvhT<8, 8>;
#endif
#if defined(__AVX512BW__)
template class TriangleBvhT<16, 4>;
template class TriangleBvhT<16, 8>;
#endif

}  // namespace foton::kern
