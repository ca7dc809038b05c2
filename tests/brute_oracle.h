#pragma once
// The brute-force closest-hit oracle of the grid tests: every triangle of a mesh, packed into
// SIMD blocks. The block kernel equals its scalar twin bit for bit (test_moller_trumbore) and
// is 16x cheaper as an oracle.
#include <numeric>
#include <vector>

#include "engine/scene/mesh.h"
#include "kernels/moller_trumbore.h"

namespace foton::test {

struct BruteOracle {
    std::vector<kern::TriangleBlock> blocks;
    explicit BruteOracle(const TriangleMesh& m) {
        std::vector<uint32_t> ids(m.num_triangles());
        std::iota(ids.begin(), ids.end(), 0u);
        kern::pack_triangle_blocks(m.positions.data(), m.indices.data(), ids.data(), ids.size(),
                                   blocks);
    }
    bool closest(const kern::Ray1& r, kern::TriHit& h) const {
        h.t = r.tmax;
        bool any = false;
        for (const auto& b : blocks) any |= kern::intersect_block(r, b, h);
        return any;
    }
};

}  // namespace foton::test
