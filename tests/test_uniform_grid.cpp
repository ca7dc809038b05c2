// The triangle grid kernel returns exactly the brute-force closest hit.
#include <catch2/catch.hpp>
#include <numeric>
#include <random>

#include "brute_oracle.h"
#include "engine/scene/obj_loader.h"
#include "kernels/uniform_grid.h"
#include "test_util.h"

using namespace foton;
using namespace foton::kern;

TEST_CASE("uniform grid equals brute force on the bunny", "[kernel][grid]") {
    const TriangleMesh mesh = load_obj(test::shared_path("meshes/bunny.obj")).mesh;
    const test::BruteOracle brute(mesh);
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> U(0.f, 1.f);
    const Bounds3 bb = mesh.bounds();
    const Vec3 ext = bb.diagonal();
    for (float density : {0.25f, 0.5f, 2.f}) {
        UniformGrid grid;
        GridParams gp;
        gp.cells_per_triangle = density;
        grid.build(mesh.positions.data(), mesh.indices.data(), mesh.num_triangles(), gp);
        std::size_t hits = 0;
        const int n = test::scaled(20000);
        for (int i = 0; i < n; ++i) {
            // Origins around the mesh; directions either random or aimed at a surface point.
            const Vec3 o =
                bb.lo - ext * 0.5f + Vec3{U(rng) * ext.x, U(rng) * ext.y, U(rng) * ext.z} * 2.f;
            Vec3 d{U(rng) - 0.5f, U(rng) - 0.5f, U(rng) - 0.5f};
            if (i % 2 == 0) {
                Vec3 p0, p1, p2;
                mesh.corners(uint32_t(rng() % mesh.num_triangles()), p0, p1, p2);
                const float a = U(rng), b = U(rng) * (1.f - a);
                d = p0 + (p1 - p0) * a + (p2 - p0) * b - o;
            }
            Ray1 r{o.x, o.y, o.z, d.x, d.y, d.z, 0.f, i % 7 == 0 ? 0.5f : kInf};
            TriHit hb, hg;
            const bool b = brute.closest(r, hb);
            hg.t = r.tmax;
            const bool g = grid.intersect(r, hg);
            REQUIRE(b == g);
            REQUIRE(grid.occluded(r) == b);
            if (b) {
                ++hits;
                // Equal t; the ids may differ only on an exact tie (a shared edge or vertex).
                REQUIRE(hg.t == hb.t);
            }
        }
        CHECK(hits > n / 3);
    }
}

TEST_CASE("uniform grid handles flat, tiny and empty inputs", "[kernel][grid]") {
    // A single axis-aligned quad: a flat bounding box.
    const float pos[] = {0, 0, 0, 1, 0, 0, 1, 0, 1, 0, 0, 1};
    const uint32_t idx[] = {0, 1, 2, 0, 2, 3};
    UniformGrid g;
    g.build(pos, idx, 2);
    TriHit h;
    REQUIRE(g.intersect({0.3f, 1.f, 0.6f, 0.f, -1.f, 0.f, 0.f, kInf}, h));
    CHECK(h.t == Approx(1.f));
    TriHit miss;
    CHECK_FALSE(g.intersect({1.3f, 1.f, 0.6f, 0.f, -1.f, 0.f, 0.f, kInf}, miss));
    // A ray lying in the plane of the quad misses (parallel).
    TriHit graze;
    CHECK_FALSE(g.intersect({-1.f, 0.f, 0.5f, 1.f, 0.f, 0.f, 0.f, kInf}, graze));
    UniformGrid empty;
    empty.build(pos, idx, 0);
    TriHit e;
    CHECK_FALSE(empty.intersect({0, 0, 0, 1, 0, 0, 0, kInf}, e));
    CHECK_FALSE(empty.occluded({0, 0, 0, 1, 0, 0, 0, kInf}));
}
