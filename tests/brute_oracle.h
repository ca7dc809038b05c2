#pragma once
// The brute-force closest-hit oracle of the grid tests: every triangle of a mesh, packed into
// SIMD blocks. The block kernel equals its scalar twin bit for bit (test_moller_trumbore) and
// is 16x cheaper as an oracle. And the test of whether a hit it reports is geometric.
#include <cmath>
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

// Möller–Trumbore is unstable for a ray almost in a triangle's plane: det is tiny and t can
// come out far from where the ray meets the triangle. Brute force reports such a hit wherever
// it lands; a BVH may rightly cull it, since the point is outside the triangle's box. Such
// rays (within 0.1 degree of the hit triangle's plane, or hit outside its box) are not
// compared; they are counted, and must be rare.
inline bool geometric_hit(const TriangleMesh& m, const kern::Ray1& r, const kern::TriHit& h) {
    Vec3 p0, p1, p2;
    m.corners(h.id, p0, p1, p2);
    const Vec3 n = cross(p1 - p0, p2 - p0), d{r.dx, r.dy, r.dz};
    if (std::fabs(dot(n, d)) < 2e-3f * length(n) * length(d)) return false;
    Bounds3 b;
    b.extend(p0);
    b.extend(p1);
    b.extend(p2);
    const Vec3 p{r.ox + h.t * r.dx, r.oy + h.t * r.dy, r.oz + h.t * r.dz};
    const float tol = 1e-3f * length(b.diagonal()) + 1e-5f * length(p);
    for (int a = 0; a < 3; ++a)
        if (p[a] < b.lo[a] - tol || p[a] > b.hi[a] + tol) return false;
    return true;
}

}  // namespace foton::test
