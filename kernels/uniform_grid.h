#pragma once
// Uniform grid over a triangle mesh: cells in CSR form, each cell's triangles re-packed into
// SoA TriangleBlocks for the SIMD Möller–Trumbore kernel, traversed with the 3D DDA.
#include <cstdint>
#include <vector>

#include "grid_dda.h"
#include "huge_page_allocator.h"
#include "moller_trumbore.h"
#include "ray1.h"
#include "triangle_block.h"

namespace foton::kern {

struct GridParams {
    // Cells per triangle. With 8- or 16-wide triangle blocks a coarse grid pays: a cell's
    // triangles cost about one SIMD test, and fewer cells mean fewer DDA steps. 0.5 was the
    // best of {0.25 .. 16} on the bunny and the torus knot (AVX-512, see bench/).
    float cells_per_triangle = 0.5f;
    int max_res = 512;
    // Single-ray closest hit skips triangles already tested in an earlier cell. Off by
    // default: with W triangles per SIMD test the id lookups cost more than the retests they
    // save (measured in bench/bench_traversal.cpp, method grid_mailbox). Packet traversal
    // always uses a mailbox: there a retest costs a whole packet test.
    bool mailbox = false;
    // Nested grids (the thesis' answer to the "teapot in a stadium"): a cell holding more
    // than max(nest_min_refs, nest_factor x the mean of the non-empty cells) triangles gets a
    // grid of its own over them, down to nest_depth levels. 0 levels turns nesting off.
    int nest_depth = 2;
    uint32_t nest_min_refs = 64;
    float nest_factor = 16.f;
};

struct GridCounters {
    uint64_t cells = 0;          // cells visited
    uint64_t blocks = 0;         // triangle blocks tested (each W ray/triangle tests)
    uint64_t packet_tests = 0;   // packet traversal: one triangle against one W-ray packet
    uint64_t mailbox_skips = 0;  // triangles not retested because the mailbox had them
};

// Packet traversal takes at most this many W-wide packets at once (e.g. 8x8 camera rays as
// four 4x4 packets on AVX-512).
inline constexpr std::size_t kMaxGridPackets = 16;

class UniformGrid {
  public:
    // positions: xyz per vertex; indices: three per triangle. Triangles are identified by
    // their index in `indices`.
    void build(const float* positions, const uint32_t* indices, std::size_t num_triangles,
               const GridParams& params = {});
    // Builds over the triangles listed in `tris` only (ids into `indices`, kept as hit ids),
    // with the grid's box clipped to [clip_lo, clip_hi] when given (a nested grid covers its
    // parent cell only: large triangles reaching out of the cell must not stretch it).
    void build_subset(const float* positions, const uint32_t* indices, const uint32_t* tris,
                      std::size_t count, const GridParams& params, int depth,
                      const float* clip_lo = nullptr, const float* clip_hi = nullptr);

    // Closest hit with r.tmin < t < min(r.tmax, hit.t); updates `hit`.
    bool intersect(const Ray1& r, TriHit& hit, GridCounters* counters = nullptr) const;
    // Any hit with r.tmin < t < r.tmax.
    bool occluded(const Ray1& r, GridCounters* counters = nullptr) const;
    // Closest hits of `count` (<= kMaxGridPackets) W-ray packets traversed together as one
    // coherent bundle (grid_packet.cpp). hits[p].t holds each ray's tmax on entry (-inf for
    // an unused lane) and the hit t on return, like `intersect` does per ray.
    void intersect_packets(const RayPacket* packets, std::size_t count, PacketHits* hits,
                           GridCounters* counters = nullptr) const;

    const GridFrame& frame() const { return frame_; }
    std::size_t num_blocks() const;  // including nested grids
    std::size_t num_references() const { return references_; }
    std::size_t memory_bytes() const;
    std::size_t num_child_grids() const;
    bool empty() const { return blocks_.empty() && children_.empty(); }

  private:
    bool intersect_mailboxed(const Ray1& r, TriHit& hit, GridCounters* counters) const;
    int32_t child_of(uint32_t cell) const { return cell_child_.empty() ? -1 : cell_child_[cell]; }

    GridFrame frame_;
    bool mailbox_ = false;
    std::vector<uint32_t> cell_begin_;  // num_cells + 1 offsets into blocks_
    std::vector<TriangleBlock, HugePageAllocator<TriangleBlock>> blocks_;  // 2 MB pages
    std::size_t references_ = 0;
    // Nested grids: cell_child_[cell] indexes children_ (-1: the cell's own blocks). Empty
    // when no cell is nested.
    std::vector<int32_t> cell_child_;
    std::vector<UniformGrid> children_;
};

}  // namespace foton::kern
