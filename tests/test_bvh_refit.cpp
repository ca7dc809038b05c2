// TriangleBvhT::refit (kernels/bvh_refit.cpp): a tree moved to new vertex positions finds
// exactly what brute force finds on the moved mesh, as does its scalar twin; moved back, it is
// the tree the build made, byte for byte; triangles collapsed by the move are never hit; a
// mesh of another size is refused.
#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <stdexcept>

#include "bench/ray_sets.h"
#include "brute_oracle.h"
#include "kernels/triangle_bvh.h"

using namespace foton;
using namespace foton::kern;

namespace {

// A smooth, non-rigid deformation: a twist about y, a bulge and a shift.
TriangleMesh deformed(const TriangleMesh& m) {
    TriangleMesh d = m;
    const Bounds3 b = m.bounds();
    const Vec3 c = b.center();
    const float size = length(b.diagonal());
    for (std::size_t v = 0; v < d.num_vertices(); ++v) {
        float* p = &d.positions[3 * v];
        const float y = (p[1] - c.y) / size, ang = 0.6f * y;
        const float x = p[0] - c.x, z = p[2] - c.z;
        p[0] = c.x + x * std::cos(ang) - z * std::sin(ang) + 0.05f * size * std::sin(7.f * y);
        p[2] = c.z + x * std::sin(ang) + z * std::cos(ang) + 0.3f * size;
        p[1] += 0.02f * size * std::cos(5.f * x / size);
    }
    return d;
}

// Every ray whose brute-force hit is stable (test::geometric_hit) must get exactly it.
void check_against_brute(const TriangleBvh& bvh, const TriangleMesh& mesh,
                         const std::vector<Ray1>& rays, std::size_t& hits) {
    const test::BruteOracle brute(mesh);
    std::size_t unstable = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        INFO("ray " << i);
        TriHit b, h, s;
        const bool hb = brute.closest(rays[i], b);
        if (hb && !test::geometric_hit(mesh, rays[i], b)) {
            ++unstable;
            continue;
        }
        REQUIRE(bvh.intersect(rays[i], h) == hb);
        REQUIRE(bvh.occluded(rays[i]) == hb);
        REQUIRE(bvh.intersect_scalar(rays[i], s) == hb);
        if (!hb) continue;
        ++hits;
        REQUIRE(h.id == b.id);
        REQUIRE(h.t == b.t);
        REQUIRE(h.u == b.u);
        REQUIRE(h.v == b.v);
        REQUIRE(s.id == b.id);
    }
    CHECK(unstable <= rays.size() / 100 + 1);
}

}  // namespace

TEST_CASE("a refitted bvh finds what brute force finds on the moved mesh", "[kernel][bvh]") {
    const bench::KernelScene scene = bench::load_kernel_scene("bunny");
    const TriangleMesh& m = scene.mesh;
    TriangleBvh bvh;
    bvh.build(m.positions.data(), m.indices.data(), m.num_triangles(),
              TriangleBvh::default_params(), true);
    const TriangleBvh::NodeArray built = bvh.nodes();

    bench::KernelScene moved = scene;
    moved.mesh = deformed(m);
    const TriangleSource src{moved.mesh.positions.data(), moved.mesh.indices.data(),
                             moved.mesh.num_triangles()};
    bvh.refit(&src, 1);
    const bench::RaySets sets = bench::make_ray_sets(moved, 48, 3000);
    std::size_t hits = 0;
    check_against_brute(bvh, moved.mesh, sets.primary, hits);
    check_against_brute(bvh, moved.mesh, sets.diffuse, hits);
    check_against_brute(bvh, moved.mesh, sets.shadow, hits);
    CHECK(hits > 1000);

    // Moved back: the build's tree, byte for byte.
    const TriangleSource back{m.positions.data(), m.indices.data(), m.num_triangles()};
    bvh.refit(&back, 1);
    REQUIRE(bvh.nodes().size() == built.size());
    CHECK(std::memcmp(bvh.nodes().data(), built.data(), built.size() * sizeof(built[0])) == 0);

    // A mesh of another size is refused, and the tree is left as it was.
    const TriangleSource fewer{m.positions.data(), m.indices.data(), m.num_triangles() - 1};
    CHECK_THROWS_AS(bvh.refit(&fewer, 1), std::invalid_argument);
    CHECK(std::memcmp(bvh.nodes().data(), built.data(), built.size() * sizeof(built[0])) == 0);
}

TEST_CASE("triangles a refit collapses are never hit, and come back", "[kernel][bvh]") {
    const bench::KernelScene scene = bench::load_kernel_scene("teapot");
    TriangleMesh m = scene.mesh;
    TriangleBvh bvh;
    bvh.build(m.positions.data(), m.indices.data(), m.num_triangles(),
              TriangleBvh::default_params(), true);
    // Every vertex of the first half of the vertices moves onto the first vertex: the
    // triangles made only of those collapse to a point (zero area, never hit).
    TriangleMesh collapsed = m;
    for (std::size_t v = 1; v < m.num_vertices() / 2; ++v)
        for (int a = 0; a < 3; ++a) collapsed.positions[3 * v + a] = m.positions[a];
    const TriangleSource src{collapsed.positions.data(), collapsed.indices.data(),
                             collapsed.num_triangles()};
    bvh.refit(&src, 1);
    bench::KernelScene moved = scene;
    moved.mesh = collapsed;
    const bench::RaySets sets = bench::make_ray_sets(moved, 32, 1000);
    std::size_t hits = 0;
    check_against_brute(bvh, collapsed, sets.primary, hits);
    check_against_brute(bvh, collapsed, sets.diffuse, hits);
    CHECK(hits > 0);
    // And back: the collapsed triangles are hit again, as brute force hits them.
    const TriangleSource back{m.positions.data(), m.indices.data(), m.num_triangles()};
    bvh.refit(&back, 1);
    std::size_t hits_back = 0;
    check_against_brute(bvh, m, bench::make_ray_sets(scene, 32, 1000).primary, hits_back);
    CHECK(hits_back > 0);
}
