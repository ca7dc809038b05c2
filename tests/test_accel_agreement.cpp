// brute, brute-simd, grid, bvh, octree, kdtree and embree return identical closest hits and
// occlusion; bvh, octree and kdtree equal brute force exactly (t, u, v, primitive, geometry, ties
// included).
#include <catch2/catch.hpp>
#include <random>

#include "engine/accel/bvh_accel.h"
#include "engine/accel/intersector.h"
#include "engine/film/metrics.h"
#include "engine/scene/xml_loader.h"
#include "engine/transport/registry/render.h"
#include "test_util.h"

using namespace foton;

namespace {
void check_agreement(const Scene& scene, int n, uint32_t seed) {
    // The SIMD brute force is the oracle; the scalar one (16x slower) checks every 20th ray.
    const auto scalar = make_intersector(scene, AccelType::Brute);
    const auto brute = make_intersector(scene, AccelType::BruteSimd);
    const auto grid = make_intersector(scene, AccelType::Grid);
    const auto bvh = make_intersector(scene, AccelType::Bvh);
    const auto embree = make_intersector(scene, AccelType::Embree);
    const auto octree = make_intersector(scene, AccelType::Octree);
    const auto kdtree = make_intersector(scene, AccelType::KdTree);
    const Bounds3 bb = scene.bounds();
    const Vec3 ext = bb.diagonal();
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> U(0.f, 1.f);
    TraceCounters c;
    std::size_t hits = 0, embree_ties = 0;
    for (int i = 0; i < n; ++i) {
        const Vec3 o = bb.lo + Vec3{U(rng) * ext.x, U(rng) * ext.y, U(rng) * ext.z};
        const Vec3 target = bb.lo + Vec3{U(rng) * ext.x, U(rng) * ext.y, U(rng) * ext.z};
        const Vec3 d = normalize(target - o);
        const kern::Ray1 r{o.x, o.y, o.z, d.x,
                           d.y, d.z, 0.f, i % 5 == 0 ? 0.3f * length(ext) : kInfinity};
        Hit1 hb, hs, hg, he, hv, ho, hk;
        const bool b = brute->intersect1(r, hb, c);
        if (i % 20 == 0) {
            REQUIRE(scalar->intersect1(r, hs, c) == b);
            REQUIRE(scalar->occluded1(r, c) == b);
        } else {
            hs = hb;
        }
        REQUIRE(grid->intersect1(r, hg, c) == b);
        REQUIRE(octree->intersect1(r, ho, c) == b);
        REQUIRE(kdtree->intersect1(r, hk, c) == b);
        REQUIRE(embree->intersect1(r, he, c) == b);
        REQUIRE(bvh->intersect1(r, hv, c) == b);
        REQUIRE(bvh->occluded1(r, c) == b);
        const bool occ = brute->occluded1(r, c);
        REQUIRE(occ == b);
        REQUIRE(grid->occluded1(r, c) == occ);
        REQUIRE(octree->occluded1(r, c) == occ);
        REQUIRE(kdtree->occluded1(r, c) == occ);
        REQUIRE(embree->occluded1(r, c) == occ);
        if (!b) continue;
        ++hits;
        REQUIRE(hs.geom == hb.geom);
        REQUIRE(hs.prim == hb.prim);
        REQUIRE(hs.t == hb.t);
        REQUIRE(hg.geom == hb.geom);
        REQUIRE(hg.t == hb.t);  // so a different prim can only be an exact tie
        // The trees break ties as brute force does (the smaller id), like the bvh.
        REQUIRE(ho.geom == hb.geom);
        REQUIRE(ho.prim == hb.prim);
        REQUIRE(ho.t == hb.t);
        REQUIRE(hk.geom == hb.geom);
        REQUIRE(hk.prim == hb.prim);
        REQUIRE(hk.t == hb.t);
        REQUIRE(hv.geom == hb.geom);
        REQUIRE(hv.prim == hb.prim);
        REQUIRE(hv.t == hb.t);
        REQUIRE(hv.u == hb.u);
        REQUIRE(hv.v == hb.v);
        REQUIRE(he.geom == hb.geom);
        if (he.prim == hb.prim) {
            REQUIRE(he.t == hb.t);  // re-evaluated with our arithmetic: bit-identical
            REQUIRE(he.u == hb.u);
        } else {
            // Embree may pick the other triangle of a shared edge: same distance.
            ++embree_ties;
            REQUIRE(he.t == Approx(hb.t).epsilon(1e-5));
        }
    }
    CHECK(hits > std::size_t(n) / 10);
    CHECK(embree_ties <= std::size_t(n) / 1000);
}
}  // namespace

TEST_CASE("accelerators agree on 100k random rays over the bunny", "[accel]") {
    const Scene scene = load_scene(test::source_path("scenes/bunny.xml"));
    check_agreement(scene, test::scaled(100000), 11);
}

TEST_CASE("accelerators agree on the Cornell box", "[accel]") {
    const Scene scene = load_scene(test::source_path("scenes/cornell-box.xml"));
    check_agreement(scene, 100000, 12);
}

TEST_CASE("accelerators agree in the batch interface", "[accel]") {
    const Scene scene = load_scene(test::source_path("scenes/cornell-mirror.xml"));
    RayBatch rays;
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> U(-1.f, 1.f);
    for (uint32_t i = 0; i < 5000; ++i)
        rays.push({278.f + 200.f * U(rng), 277.f + 200.f * U(rng), 200.f + 100.f * U(rng)},
                  normalize(Vec3{U(rng), U(rng), U(rng)}), 0.f, kInfinity, i);
    HitBatch ref, other;
    std::vector<uint8_t> occ_ref, occ;
    TraceCounters c;
    const auto brute = make_intersector(scene, AccelType::Brute);
    brute->intersect(rays, ref, c);
    brute->occluded(rays, occ_ref, c);
    for (AccelType a : {AccelType::BruteSimd, AccelType::Grid, AccelType::Bvh, AccelType::Embree,
                        AccelType::Octree, AccelType::KdTree}) {
        const auto acc = make_intersector(scene, a);
        acc->intersect(rays, other, c);
        acc->occluded(rays, occ, c);
        for (std::size_t i = 0; i < rays.size(); ++i) {
            REQUIRE(other.geom[i] == ref.geom[i]);
            if (ref.geom[i] != kNoHit) REQUIRE(other.t[i] == Approx(ref.t[i]).epsilon(1e-6));
            REQUIRE(occ[i] == occ_ref[i]);
        }
    }
}

TEST_CASE("bvh equals brute force exactly on the mixed sphere and mesh scenes", "[accel][bvh]") {
    // Several spheres (materials.xml has nine) and meshes in one scene: the sphere BVH and the
    // triangle BVH together return brute force's hit, ties between spheres included.
    for (const char* name : {"scenes/materials.xml", "scenes/mis-plates.xml"}) {
        INFO(name);
        const Scene scene = load_scene(test::source_path(name));
        const auto brute = make_intersector(scene, AccelType::BruteSimd);
        const auto bvh = make_intersector(scene, AccelType::Bvh);
        const Bounds3 bb = scene.bounds();
        const Vec3 ext = bb.diagonal();
        std::mt19937 rng(21);
        std::uniform_real_distribution<float> U(0.f, 1.f);
        TraceCounters c;
        std::size_t hits = 0;
        for (int i = 0; i < 20000; ++i) {
            const Vec3 o = bb.lo + Vec3{U(rng) * ext.x, U(rng) * ext.y, U(rng) * ext.z};
            const Vec3 d = normalize(Vec3{U(rng) - 0.5f, U(rng) - 0.5f, U(rng) - 0.5f});
            const kern::Ray1 r{o.x, o.y, o.z, d.x, d.y, d.z, 1e-4f, kInfinity};
            Hit1 hb, hv;
            const bool b = brute->intersect1(r, hb, c);
            REQUIRE(bvh->intersect1(r, hv, c) == b);
            REQUIRE(bvh->occluded1(r, c) == b);
            if (!b) continue;
            ++hits;
            REQUIRE(hv.geom == hb.geom);
            REQUIRE(hv.prim == hb.prim);
            REQUIRE(hv.t == hb.t);
        }
        CHECK(hits > 5000);
    }
}

TEST_CASE(
    "octree and kdtree equal brute force on axis-aligned rays and on mixed sphere and mesh scenes",
    "[accel][octree][kdtree]") {
    // Rays along the axes run in the octree's mid-planes and the box's walls (the Cornell
    // box's walls lie in them, and so do the kd-tree's planes, cut where triangles start and
    // end): a walk must order the children of a direction without an x, y or z component as
    // the line does, and find triangles touching a plane the ray runs in. Random rays over
    // scenes with spheres and meshes.
    for (const auto& [name, accel] : {std::pair{"scenes/cornell-box.xml", AccelType::Octree},
                                      std::pair{"scenes/materials.xml", AccelType::Octree},
                                      std::pair{"scenes/mis-plates.xml", AccelType::Octree},
                                      std::pair{"scenes/cornell-box.xml", AccelType::KdTree},
                                      std::pair{"scenes/materials.xml", AccelType::KdTree},
                                      std::pair{"scenes/mis-plates.xml", AccelType::KdTree}}) {
        INFO(name << " " << accel_name(accel));
        const Scene scene = load_scene(test::source_path(name));
        const auto brute = make_intersector(scene, AccelType::BruteSimd);
        const auto octree = make_intersector(scene, accel);
        const Bounds3 bb = scene.bounds();
        const Vec3 ext = bb.diagonal();
        std::mt19937 rng(5);
        std::uniform_real_distribution<float> U(0.f, 1.f);
        TraceCounters c;
        std::size_t hits = 0;
        for (int i = 0; i < 30000; ++i) {
            // Points on a lattice of eighths (the octree's planes) every third ray.
            auto coord = [&](int a) {
                const float f = i % 3 == 0 ? float(int(U(rng) * 9.f)) / 8.f : U(rng);
                return bb.lo[a] + f * ext[a];
            };
            const Vec3 o{coord(0), coord(1), coord(2)};
            Vec3 d;
            if (i % 2 == 0) {
                d = Vec3{0.f, 0.f, 0.f};
                const int axis = int(U(rng) * 3.f) % 3;
                (axis == 0 ? d.x : axis == 1 ? d.y : d.z) = U(rng) < 0.5f ? -1.f : 1.f;
            } else {
                d = normalize(Vec3{U(rng) - 0.5f, U(rng) - 0.5f, U(rng) - 0.5f});
            }
            const kern::Ray1 r{o.x, o.y, o.z,   d.x,
                               d.y, d.z, 1e-4f, i % 7 == 0 ? 0.2f * length(ext) : kInfinity};
            Hit1 hb, ho;
            const bool b = brute->intersect1(r, hb, c);
            REQUIRE(octree->intersect1(r, ho, c) == b);
            REQUIRE(octree->occluded1(r, c) == brute->occluded1(r, c));
            if (!b) continue;
            ++hits;
            REQUIRE(ho.geom == hb.geom);
            REQUIRE(ho.prim == hb.prim);
            REQUIRE(ho.t == hb.t);
        }
        CHECK(hits > 5000);
    }
}

TEST_CASE("batch intersect equals per-ray intersect1 for every backend", "[accel][bvh]") {
    // Camera rays (coherent: the bvh traces them as packets) and shadow rays from their hits to
    // a point, with the batch flagged coherent and not; each must give every ray exactly what
    // the backend's single-ray form gives it.
    for (const char* name :
         {"scenes/bunny.xml", "scenes/materials.xml", "scenes/cornell-box.xml"}) {
        INFO(name);
        const Scene scene = load_scene(test::source_path(name));
        RayBatch cam;
        const int w = 48, h = 36;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x)
                for (int s = 0; s < 2; ++s) {
                    Vec3 o, d;
                    scene.camera.generate(
                        (float(x) + 0.25f + 0.5f * float(s)) * float(scene.film.width) / float(w),
                        (float(y) + 0.5f) * float(scene.film.height) / float(h), {0.5f, 0.5f}, o,
                        d);
                    cam.push(o, d, 0.f, kInfinity, uint32_t(cam.size()));
                }
        // Beside the eye: most camera hits see it, some are hidden.
        const Vec3 light = scene.camera.eye + (scene.camera.u + scene.camera.v) *
                                                  (0.15f * length(scene.bounds().diagonal()));
        std::vector<std::unique_ptr<Intersector>> backends;
        for (AccelType a : {AccelType::BruteSimd, AccelType::Grid, AccelType::Bvh,
                            AccelType::Embree, AccelType::Octree, AccelType::KdTree})
            backends.push_back(make_intersector(scene, a));
        // The bvh with every incoherent batch through the stream kernel (by default only trees
        // larger than the caches take it, and these are small).
        backends.push_back(std::make_unique<BvhAccel>(scene, 0, 0));
        for (std::size_t k = 0; k < backends.size(); ++k) {
            INFO("backend " << k << ": " << backends[k]->name());
            const Intersector* acc = backends[k].get();
            const bool is_bvh = std::string(acc->name()) == "bvh";
            TraceCounters c;
            RayBatch shadow;
            uint64_t nodes[2] = {0, 0};  // bvh nodes tested: coherent batch, ray by ray
            for (bool coherent : {true, false}) {
                cam.coherent = coherent;
                HitBatch hits;
                const uint64_t before = c.bvh_nodes;
                acc->intersect(cam, hits, c);
                nodes[coherent ? 0 : 1] = c.bvh_nodes - before;
                REQUIRE(hits.size() == cam.size());
                std::size_t n_hits = 0;
                for (std::size_t i = 0; i < cam.size(); ++i) {
                    Hit1 one;
                    const bool hit = acc->intersect1(ray_at(cam, i), one, c);
                    REQUIRE((hits.geom[i] != kNoHit) == hit);
                    if (!hit) continue;
                    ++n_hits;
                    REQUIRE(hits.t[i] == one.t);
                    REQUIRE(hits.u[i] == one.u);
                    REQUIRE(hits.v[i] == one.v);
                    REQUIRE(hits.prim[i] == one.prim);
                    REQUIRE(hits.geom[i] == one.geom);
                    if (coherent) {
                        const Vec3 p = cam.origin(i) + cam.direction(i) * (hits.t[i] * 0.999f);
                        shadow.push(p, normalize(light - p), 0.f, length(light - p), uint32_t(i));
                    }
                }
                CHECK(n_hits > cam.size() / 10);
            }
            // The bvh takes the coherent batch as packets: far fewer node tests (on the bunny;
            // the other two scenes' trees are a single leaf).
            if (is_bvh && std::string(name) == "scenes/bunny.xml") CHECK(2 * nodes[0] < nodes[1]);
            REQUIRE(!shadow.empty());
            for (bool coherent : {true, false}) {
                shadow.coherent = coherent;
                std::vector<uint8_t> occ;
                acc->occluded(shadow, occ, c);
                REQUIRE(occ.size() == shadow.size());
                std::size_t blocked = 0;
                for (std::size_t i = 0; i < shadow.size(); ++i) {
                    REQUIRE(bool(occ[i]) == acc->occluded1(ray_at(shadow, i), c));
                    blocked += occ[i];
                }
                CHECK(blocked < shadow.size());
                CHECK(blocked > 0);
            }
        }
    }
}

namespace {

// The torus knot placed four times (one mirrored, one squashed) with a sphere and a quad: a
// file placed more than once is instanced.
const char* kInstancedKnots = R"(<scene><objects>
  <triangle_mesh src="meshes/torus-knot.obj"><material type="lambert"/></triangle_mesh>
  <triangle_mesh src="meshes/torus-knot.obj"><material type="lambert"/>
    <transform><rotate x="0" y="1" z="0" angle="40"/><translate x="3" y="0" z="0"/></transform></triangle_mesh>
  <triangle_mesh src="meshes/torus-knot.obj"><material type="lambert"/>
    <transform><scale x="-1" y="1" z="1"/><translate x="0" y="0" z="3"/></transform></triangle_mesh>
  <triangle_mesh src="meshes/torus-knot.obj" smooth="false"><material type="lambert"/>
    <transform><scale x="1" y="0.4" z="1.5"/><rotate x="1" y="0" z="1" angle="30"/>
      <translate x="3" y="0.5" z="3"/></transform></triangle_mesh>
  <sphere radius="0.7"><center x="1.5" y="0" z="1.5"/><material type="lambert"/></sphere>
  <quad><corner x="-2" y="-1.2" z="-2"/><edge1 x="0" y="0" z="7"/><edge2 x="7" y="0" z="0"/>
    <material type="lambert"/></quad>
</objects><film width="8" height="8"/>
<camera><eye x="1.5" y="4" z="-6"/><target x="1.5" y="0" z="1.5"/></camera></scene>)";

}  // namespace

TEST_CASE("accelerators agree on instanced meshes, one stored mesh for four placements",
          "[accel][instance]") {
    const Scene scene = parse_scene(kInstancedKnots, "knots.xml", test::source_path("scenes"));
    REQUIRE(scene.instances.size() == 4);
    CHECK(scene.meshes.size() == 2);  // the knot once, the quad
    CHECK(scene.num_triangles() == 4 * 4096 + 2);
    CHECK(scene.num_stored_triangles() == 4096 + 2);
    CHECK(scene.summary().find("instances  4 placements") != std::string::npos);
    check_agreement(scene, test::scaled(60000), 13);
    // The batch interface (coherent and not) equals the single-ray one.
    const Bounds3 bb = scene.bounds();
    for (AccelType a : {AccelType::Brute, AccelType::Grid, AccelType::Bvh, AccelType::Embree}) {
        const auto acc = make_intersector(scene, a);
        for (bool coherent : {false, true}) {
            RayBatch rays;
            rays.coherent = coherent;
            for (int i = 0; i < 997; ++i) {
                const float fx = float(i % 31) / 30.f, fz = float(i / 31) / 32.f;
                const Vec3 o{1.5f, 4.f, -6.f};
                const Vec3 target{bb.lo.x + fx * (bb.hi.x - bb.lo.x), 0.f,
                                  bb.lo.z + fz * (bb.hi.z - bb.lo.z)};
                rays.push(o, normalize(target - o), 0.f, kInfinity, uint32_t(i));
            }
            HitBatch hits;
            std::vector<uint8_t> occ;
            TraceCounters c;
            acc->intersect(rays, hits, c);
            acc->occluded(rays, occ, c);
            for (std::size_t i = 0; i < rays.size(); ++i) {
                Hit1 h;
                const bool any = acc->intersect1(ray_at(rays, i), h, c);
                REQUIRE(hits.geom[i] == h.geom);
                REQUIRE(hits.t[i] == h.t);
                REQUIRE(bool(occ[i]) == any);
            }
            if (a != AccelType::Embree) CHECK(c.instance_visits > 0);  // Embree counts nothing
        }
    }
}

TEST_CASE("instanced meshes render as their copies do", "[accel][instance][integrator]") {
    // The same four placements written with four spellings of the path are four files to the
    // loader, hence copies moved into world space.
    std::string copies = kInstancedKnots;
    const std::string from = "src=\"meshes/torus-knot.obj\"";
    const char* spellings[] = {"src=\"./meshes/torus-knot.obj\"", "src=\"meshes/./torus-knot.obj\"",
                               "src=\"meshes/../meshes/torus-knot.obj\""};
    for (const char* s : spellings) copies.replace(copies.rfind(from), from.size(), s);
    auto render_scene = [](const std::string& text) {
        std::string t = text;
        t.replace(t.find("<objects>"), 9,
                  "<lights><environment intensity=\"1\"/></lights><objects>");
        t.replace(t.find("<film width=\"8\" height=\"8\"/>"), 28,
                  "<film width=\"48\" height=\"32\"/><renderer type=\"path\" max_depth=\"3\"/>");
        TestScene s(parse_scene(t, "knots.xml", test::source_path("scenes")));
        const auto acc = make_intersector(s, AccelType::Bvh);
        RenderOptions opt;
        opt.spp = 16;
        opt.seed = 5;
        return std::make_pair(s.instances.size(), render(s, s.render, *acc, opt).film);
    };
    const auto [n_inst, inst] = render_scene(kInstancedKnots);
    const auto [n_copy, copy] = render_scene(copies);
    REQUIRE(n_inst == 4);
    REQUIRE(n_copy == 0);
    const ImageError e = compare_images(inst, copy);
    double mean = 0.0;
    for (const RGB& p : copy.pixels) mean += p.luminance();
    mean /= double(copy.pixels.size());
    INFO("RMSE " << e.rmse << ", max " << e.max_abs << ", mean " << mean);
    // Rounding differs (a placed triangle vs a moved one), so a few paths may branch apart.
    // (One light: with several, the scene's bounds, looser around instances, would change
    // the lights' selection probabilities and so every path's noise, not its expectation.)
    CHECK(e.rmse < 1e-3 * mean);
}
