#pragma once
// Triangles pre-packed for the SIMD Möller–Trumbore kernel: M triangles per block, one per
// lane, stored as v0 and the two edges e1 = v1 - v0, e2 = v2 - v0. Unused lanes are inert:
// zero edges give det = 0, which the kernel rejects, so no tail masks are needed. The grid
// and brute force use the widest blocks (M = W); BVH leaves use narrower ones (bvh_node.h).
#include <cstdint>
#include <vector>

#include "ray1.h"
#include "simd.h"

namespace foton::kern {

inline constexpr std::size_t kBlockWidth = simd::kWidth;

template <std::size_t M>
struct alignas(M * 4 < 64 ? M * 4 : 64) TriangleBlockT {  // rows stay aligned, no padding
    static constexpr std::size_t kLanes = M;
    float v0x[M], v0y[M], v0z[M];
    float e1x[M], e1y[M], e1z[M];
    float e2x[M], e2y[M], e2z[M];
    uint32_t id[M];

    void clear();
    // Puts triangle (p0, p1, p2) with user id `tri_id` into lane `lane`.
    void set(std::size_t lane, const float* p0, const float* p1, const float* p2, uint32_t tri_id);
};
using TriangleBlock = TriangleBlockT<kBlockWidth>;

template <std::size_t M>
inline void TriangleBlockT<M>::clear() {
    for (std::size_t i = 0; i < M; ++i) {
        v0x[i] = v0y[i] = v0z[i] = 0.f;
        e1x[i] = e1y[i] = e1z[i] = 0.f;
        e2x[i] = e2y[i] = e2z[i] = 0.f;
        id[i] = kInvalidId;
    }
}

template <std::size_t M>
inline void TriangleBlockT<M>::set(std::size_t lane, const float* p0, const float* p1,
                                   const float* p2, uint32_t tri_id) {
    v0x[lane] = p0[0];
    v0y[lane] = p0[1];
    v0z[lane] = p0[2];
    e1x[lane] = p1[0] - p0[0];
    e1y[lane] = p1[1] - p0[1];
    e1z[lane] = p1[2] - p0[2];
    e2x[lane] = p2[0] - p0[0];
    e2y[lane] = p2[1] - p0[1];
    e2z[lane] = p2[2] - p0[2];
    id[lane] = tri_id;
}

// Packs the triangles listed in `tris` (indices into the index buffer) into consecutive
// blocks, appended to `out`, in the order given. `positions` is xyz-interleaved and
// `indices` holds three vertex indices per triangle; the lane id is the triangle index.
template <class BlockVector>
void pack_triangle_blocks(const float* positions, const uint32_t* indices, const uint32_t* tris,
                          std::size_t count, BlockVector& out) {
    for (std::size_t first = 0; first < count; first += kBlockWidth) {
        TriangleBlock& b = out.emplace_back();
        b.clear();
        for (std::size_t lane = 0; lane < kBlockWidth && first + lane < count; ++lane) {
            const uint32_t t = tris[first + lane];
            b.set(lane, positions + 3 * indices[3 * t], positions + 3 * indices[3 * t + 1],
                  positions + 3 * indices[3 * t + 2], t);
        }
    }
}

}  // namespace foton::kern
