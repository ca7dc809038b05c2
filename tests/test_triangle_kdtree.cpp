// The SAH kd-tree kernel returns exactly the brute-force closest hit, on a real mesh and on
// triangle soups made to stress the build: big triangles cut by many planes (perfect splits
// clip them), triangles lying in candidate planes, degenerate ones, rays along the axes.
#include <catch2/catch.hpp>
#include <functional>
#include <random>

#include "brute_oracle.h"
#include "engine/scene/obj_loader.h"
#include "kernels/triangle_kdtree.h"
#include "test_util.h"

using namespace foton;
using namespace foton::kern;

namespace {

// Rays from around the mesh, half aimed at a point on a random triangle, every fourth along
// an axis from a point on a lattice (planes the tree may split at); every hit compared.
void check_against_brute(const TriangleMesh& mesh, const TriangleKdTree& tree, int n,
                         uint32_t seed) {
    const test::BruteOracle brute(mesh);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> U(0.f, 1.f);
    const Bounds3 bb = mesh.bounds();
    const Vec3 ext = bb.diagonal();
    std::size_t hits = 0, skipped = 0;
    for (int i = 0; i < n; ++i) {
        Vec3 o = bb.lo - ext * 0.25f + Vec3{U(rng) * ext.x, U(rng) * ext.y, U(rng) * ext.z} * 1.5f;
        Vec3 d{U(rng) - 0.5f, U(rng) - 0.5f, U(rng) - 0.5f};
        if (i % 4 == 3) {
            for (int a = 0; a < 3; ++a) o[a] = bb.lo[a] + float(int(U(rng) * 9.f)) / 8.f * ext[a];
            d = Vec3{0.f, 0.f, 0.f};
            d[int(rng() % 3)] = U(rng) < 0.5f ? -1.f : 1.f;
        } else if (i % 2 == 0) {
            Vec3 p0, p1, p2;
            mesh.corners(uint32_t(rng() % mesh.num_triangles()), p0, p1, p2);
            const float a = U(rng), b = U(rng) * (1.f - a);
            d = p0 + (p1 - p0) * a + (p2 - p0) * b - o;
        }
        const Ray1 r{o.x, o.y, o.z, d.x, d.y, d.z, 0.f, i % 7 == 0 ? 0.5f : kInf};
        TriHit hb, hk;
        const bool b = brute.closest(r, hb);
        if (b && !test::geometric_hit(mesh, r, hb)) {
            ++skipped;  // a grazing hit outside its triangle's box (brute_oracle.h)
            continue;
        }
        hk.t = r.tmax;
        TreeCounters c;
        REQUIRE(tree.intersect(r, hk, &c) == b);
        REQUIRE(tree.occluded(r) == b);
        if (b) {
            ++hits;
            REQUIRE(c.nodes > 0);
            REQUIRE(hk.t == hb.t);
            REQUIRE(hk.id == hb.id);  // a tie (a shared edge) to the smaller id, as brute force
        }
    }
    CHECK(hits > std::size_t(n) / 5);
    CHECK(skipped <= std::size_t(n) / 500);
}

TriangleMesh soup(uint32_t seed) {
    // 600 small triangles, 40 large ones across the whole box, 60 axis-aligned ones on the
    // lattice of eighths (each lying in a plane a split may take), 10 degenerate (a repeated
    // corner: a segment).
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> U(0.f, 1.f);
    TriangleMesh m;
    auto add = [&](const Vec3& a, const Vec3& b, const Vec3& c) {
        const auto base = uint32_t(m.num_vertices());
        for (const Vec3& p : {a, b, c}) m.positions.insert(m.positions.end(), {p.x, p.y, p.z});
        m.indices.insert(m.indices.end(), {base, base + 1, base + 2});
    };
    auto point = [&] { return Vec3{U(rng), U(rng), U(rng)}; };
    for (int i = 0; i < 600; ++i) {
        const Vec3 c = point();
        add(c, c + (point() - Vec3{0.5f, 0.5f, 0.5f}) * 0.08f,
            c + (point() - Vec3{0.5f, 0.5f, 0.5f}) * 0.08f);
    }
    for (int i = 0; i < 40; ++i) add(point(), point(), point());
    for (int i = 0; i < 60; ++i) {
        const int axis = i % 3;
        Vec3 a = point(), b = point(), c = point();
        a[axis] = b[axis] = c[axis] = float(int(U(rng) * 9.f)) / 8.f;
        add(a, b, c);
    }
    for (int i = 0; i < 10; ++i) {
        const Vec3 a = point(), b = point();
        add(a, b, a);
    }
    return m;
}

}  // namespace

TEST_CASE("kd-tree equals brute force on the bunny", "[kernel][kdtree]") {
    const TriangleMesh mesh = load_obj(test::shared_path("meshes/bunny.obj")).mesh;
    TriangleKdTree tree;
    tree.build(mesh.positions.data(), mesh.indices.data(), mesh.num_triangles());
    INFO("nodes " << tree.num_nodes() << ", depth " << tree.depth());
    CHECK(tree.num_references() >= mesh.num_triangles());
    CHECK(tree.depth() <= KdTreeParams::kMaxDepth);
    // The SAH tree must beat testing every triangle, by far.
    CHECK(tree.sah_cost() < 0.01 * KdTreeParams{}.intersection_cost * double(mesh.num_triangles()));
    check_against_brute(mesh, tree, test::scaled(30000), 3);
}

TEST_CASE("kd-tree equals brute force on triangle soups that stress its splits",
          "[kernel][kdtree]") {
    for (uint32_t seed : {1u, 2u}) {
        const TriangleMesh mesh = soup(seed);
        for (const bool shallow : {false, true}) {
            INFO("seed " << seed << (shallow ? ", depth 3" : ""));
            KdTreeParams p;
            if (shallow) p.max_depth = 3;  // big leaves: many triangles in each
            TriangleKdTree tree;
            tree.build(mesh.positions.data(), mesh.indices.data(), mesh.num_triangles(), p);
            if (shallow) CHECK(tree.depth() <= 3);
            check_against_brute(mesh, tree, test::scaled(20000), seed + 10);
        }
    }
}

TEST_CASE("kd-tree handles flat, single and empty inputs", "[kernel][kdtree]") {
    // An axis-aligned quad: a flat box, no plane inside it along y.
    const float pos[] = {0, 0, 0, 1, 0, 0, 1, 0, 1, 0, 0, 1};
    const uint32_t idx[] = {0, 1, 2, 0, 2, 3};
    TriangleKdTree t;
    t.build(pos, idx, 2);
    TriHit h;
    REQUIRE(t.intersect({0.3f, 1.f, 0.6f, 0.f, -1.f, 0.f, 0.f, kInf}, h));
    CHECK(h.t == Approx(1.f));
    TriHit miss;
    CHECK_FALSE(t.intersect({1.3f, 1.f, 0.6f, 0.f, -1.f, 0.f, 0.f, kInf}, miss));
    CHECK_FALSE(t.occluded({0.3f, 1.f, 0.6f, 0.f, -1.f, 0.f, 0.f, 0.5f}));  // stops short
    TriHit graze;  // in the quad's plane: parallel, no hit
    CHECK_FALSE(t.intersect({-1.f, 0.f, 0.5f, 1.f, 0.f, 0.f, 0.f, kInf}, graze));
    TriangleKdTree one;
    one.build(pos, idx, 1);
    CHECK(one.num_nodes() == 1);
    TriangleKdTree empty;
    empty.build(pos, idx, 0);
    TriHit e;
    CHECK(empty.empty());
    CHECK_FALSE(empty.intersect({0, 0, 0, 1, 0, 0, 0, kInf}, e));
    CHECK_FALSE(empty.occluded({0, 0, 0, 1, 0, 0, 0, kInf}));
}

TEST_CASE("kd-tree built in parallel is the tree built on one thread", "[kernel][kdtree]") {
    const TriangleMesh mesh = load_obj(test::shared_path("meshes/bunny.obj")).mesh;
    KdTreeParams seq;
    seq.parallel_grain = 1024;  // split the work even on this small mesh
    KdTreeParams par = seq;
    // Jobs run in the reverse order (as another thread might): the result must not care.
    par.parallel = [](const std::function<void()>& a, const std::function<void()>& b) {
        b();
        a();
    };
    TriangleKdTree one, two;
    one.build(mesh.positions.data(), mesh.indices.data(), mesh.num_triangles(), seq);
    two.build(mesh.positions.data(), mesh.indices.data(), mesh.num_triangles(), par);
    REQUIRE(one.num_nodes() == two.num_nodes());
    CHECK(one.num_references() == two.num_references());
    CHECK(one.num_leaves() == two.num_leaves());
    CHECK(one.depth() == two.depth());
    CHECK(one.sah_cost() == two.sah_cost());
    CHECK(one.memory_bytes() == two.memory_bytes());
    std::mt19937 rng(4);
    std::uniform_real_distribution<float> U(-0.2f, 0.2f);
    int hits = 0;
    for (int i = 0; i < 2000; ++i) {
        // From around the bunny towards one of its vertices.
        const Vec3 o{U(rng), U(rng), U(rng)};
        const Vec3 d = mesh.vertex(mesh.indices[rng() % mesh.indices.size()]) - o;
        const Ray1 r{o.x, o.y, o.z, d.x, d.y, d.z, 0.f, kInf};
        TriHit a, b;
        TreeCounters ca, cb;
        const bool ha = one.intersect(r, a, &ca);
        hits += ha;
        CHECK(ha == two.intersect(r, b, &cb));
        CHECK(a.t == b.t);
        CHECK(a.id == b.id);
        CHECK(ca.nodes == cb.nodes);  // the same walk: the same nodes in the same places
    }
    CHECK(hits > 1000);  // the rays meet the bunny: the walks compared are real ones
}
