#pragma once
// A wide BVH over triangles: the binned SAH build of bvh_build.h collapsed to N-wide nodes
// (bvh_node.h), with leaves of M-wide SoA triangle blocks tested by the Möller–Trumbore kernel.
//
// Single-ray traversal (closest hit): one SIMD slab test gives the N children's entry
// distances; a lone hit child is entered at once, two are ordered by one compare, more are
// pushed and sorted on the stack (insertion sort of at most N entries) so the nearest is
// entered and the rest are popped near to far, each skipped if a hit closer than its entry was
// found meanwhile. Any hit (occlusion) needs no order and stops at the first hit. Written after
// reading Wald et al. 2008 (multi-branching BVHs) and Fuetterling et al. 2017 (single rays on
// wide vector units).
//
// The closest hit is canonical: the least (t, id) over all triangles, where id is the
// triangle's index in the input (meshes concatenated in order). Brute force over the same
// triangles in id order returns exactly that hit, and so does the scalar twin here, a plain
// binary-BVH traversal over the same build with the scalar Möller–Trumbore test (the oracle of
// the tests; kept only when asked for).
#include <cstdint>
#include <vector>

#include "bvh_build.h"
#include "bvh_node.h"
#include "huge_page_allocator.h"
#include "moller_trumbore.h"
#include "ray1.h"
#include "ray_stream.h"
#include "simd.h"
#include "triangle_block.h"
#include "triangle_source.h"

namespace foton::kern {

struct TriangleBvhStats {
    std::size_t triangles = 0;  // in the tree
    std::size_t skipped = 0;    // degenerate or non-finite, left out
    std::size_t nodes = 0, leaves = 0, blocks = 0;
    uint32_t depth = 0;       // wide levels
    double sah_binary = 0.0;  // SAH cost of the binary build (traversal 1, triangle 1)
    double sah_wide = 0.0;    // of the collapsed tree, same constants
    double fill = 0.0;        // used lanes / lanes of the leaf blocks
};

// How a stream form traces a batch (bvh_stream.h).
enum class StreamMode : uint8_t {
    // As given, kStreamSlots single rays in flight with their next nodes prefetched: for
    // batches without coherence on trees larger than the caches.
    Interleaved,
    // Ordered by direction octant and origin, then W consecutive rays of that order as one
    // packet (bvh_packet.h): for batches with coherence the given order hides, such as the
    // shadow rays of an image tile to several lights.
    SortedPackets,
};

template <std::size_t N, std::size_t M>
class TriangleBvhT {
  public:
    static constexpr std::size_t kWidth = N;      // children per node
    static constexpr std::size_t kLeafWidth = M;  // triangles per leaf block
    using Node = WideNode<N>;
    using Block = TriangleBlockT<M>;

    // Default build parameters for this shape: leaves of one block.
    static BvhBuildParams default_params();

    // Builds over the triangles of all sources; a triangle's id is its index in the
    // concatenation. Triangles with non-finite vertices or zero area are left out (they can
    // never be hit). keep_twin keeps the binary tree for the scalar twin.
    void build(const TriangleSource* sources, std::size_t num_sources, const BvhBuildParams& params,
               bool keep_twin = false);
    void build(const float* positions, const uint32_t* indices, std::size_t count,
               const BvhBuildParams& params, bool keep_twin = false) {
        const TriangleSource s{positions, indices, count};
        build(&s, 1, params, keep_twin);
    }

    // Moves the tree to new vertex positions with its topology kept (bvh_refit.cpp): the
    // sources must hold as many triangles as the build's (std::invalid_argument otherwise), in
    // the same order. Leaf triangles are re-packed and every box is recomputed bottom up, so
    // hits stay exact; the tree's quality falls as the geometry moves away from what it was
    // built for. Triangles the build left out stay out; a triangle moved to a non-finite or
    // degenerate position cannot be hit until it moves back. The scalar twin follows.
    void refit(const TriangleSource* sources, std::size_t num_sources);

    // Closest hit with r.tmin < t < min(r.tmax, hit.t), ties to the smaller id; updates `hit`.
    bool intersect(const Ray1& r, TriHit& hit, BvhCounters* counters = nullptr) const;
    // Any hit with r.tmin < t < r.tmax.
    bool occluded(const Ray1& r, BvhCounters* counters = nullptr) const;

    // Packet forms for coherent rays (bvh_packet.h): the rays of `p` whose bit is set in
    // `active` traverse the tree together; each gets exactly what the single-ray form gives it.
    // Closest hit: h.t, h.u, h.v, h.id hold each ray's current hit (h.t = its tmax and h.id =
    // kInvalidId when there is none yet) and are updated in place.
    void intersect_packet(const RayPacket& p, uint32_t active, PacketHits& h,
                          BvhCounters* counters = nullptr) const;
    // Any hit with tmin < t < tmax[i]; returns the occluded rays as a bit mask.
    uint32_t occluded_packet(const RayPacket& p, const float* tmax, uint32_t active,
                             BvhCounters* counters = nullptr) const;

    // Stream forms for whole batches (bvh_stream.h), each ray getting exactly what the single-ray
    // form gives it. Closest hit: out's record i is what intersect(ray i, TriHit{}) leaves in
    // its hit. Any hit: occluded[i] = 1 or 0. `mode` says how the batch is traced.
    void intersect_stream(const RayStream& rays, const HitStream& out,
                          BvhCounters* counters = nullptr,
                          StreamMode mode = StreamMode::Interleaved) const;
    void occluded_stream(const RayStream& rays, uint8_t* occluded, BvhCounters* counters = nullptr,
                         StreamMode mode = StreamMode::Interleaved) const;

    // The scalar twin (needs keep_twin): binary tree, scalar slab and triangle tests.
    bool intersect_scalar(const Ray1& r, TriHit& hit) const;
    bool occluded_scalar(const Ray1& r) const;

    bool empty() const { return root_ == kBvhEmpty; }
    const TriangleBvhStats& stats() const { return stats_; }
    std::size_t memory_bytes() const;
    using NodeArray = std::vector<Node, HugePageAllocator<Node>>;
    using BlockArray = std::vector<Block, HugePageAllocator<Block>>;
    const NodeArray& nodes() const { return nodes_; }
    const BlockArray& blocks() const { return blocks_; }
    uint32_t root() const { return root_; }

  private:
    // The single-ray traversals from a subtree (a node or leaf reference) on; the packet
    // traversal hands rays that leave its packet to these.
    bool closest_from(uint32_t start, const Ray1& r, TriHit& hit, BvhCounters* counters) const;
    bool any_from(uint32_t start, const Ray1& r, BvhCounters* counters) const;
    // The sorted stream's ray order (bvh_stream.h), in a per-thread buffer.
    const uint32_t* stream_order_of(const RayStream& rays) const;
    void intersect_sorted_packets(const RayStream& rays, const HitStream& out,
                                  BvhCounters* counters) const;
    void occluded_sorted_packets(const RayStream& rays, uint8_t* occluded,
                                 BvhCounters* counters) const;

    NodeArray nodes_;
    BlockArray blocks_;
    uint32_t root_ = kBvhEmpty;
    float packet_span_ = 0.f;  // largest origin spread of a packet (bvh_packet.h)
    float bounds_lo_[3] = {0.f, 0.f, 0.f}, bounds_hi_[3] = {0.f, 0.f, 0.f};  // the root's box
    TriangleBvhStats stats_;
    // Scalar twin: the binary tree and the triangles' corners by id.
    BinaryBvh twin_;
    std::vector<float> twin_tri_;  // 9 floats per id: p0, p1, p2
};

// The shape the engine uses: N = 8 children and leaf blocks of M = 8 triangles where the build
// has AVX (else 4 and 4). On the AVX-512 development machine 8x8 beat 8x4, 4x4 and 16x4 on
// incoherent rays of every bench scene (bench/bench_traversal.cpp, the width study).
using TriangleBvh = TriangleBvhT<simd::kHalfWidth, simd::kHalfWidth>;

}  // namespace foton::kern

#include "bvh_packet.h"
#include "bvh_stream.h"
#include "bvh_traverse.h"
