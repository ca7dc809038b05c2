// The BVH's stream forms (kernels/bvh_stream.h): every ray of a stream gets exactly what the
// single-ray form gives it (t, u, v, id bit for bit; occlusion). The interleaved mode also has
// the same traversal counters (every ray takes the same steps); sorted packets may differ where
// a hit is numerically unstable, as packets and brute force may (test_bvh.cpp).
// The single-ray form equals brute force (test_bvh.cpp), so the streams do too.
#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>

#include "bench/ray_sets.h"
#include "brute_oracle.h"
#include "kernels/triangle_bvh.h"

using namespace foton;
using namespace foton::kern;

namespace {

struct Columns {
    std::vector<float> ox, oy, oz, dx, dy, dz, tmin, tmax, t, u, v;
    std::vector<uint32_t> id;
    std::vector<uint8_t> occ;
    explicit Columns(const std::vector<Ray1>& r) {
        for (const Ray1& x : r) {
            ox.push_back(x.ox), oy.push_back(x.oy), oz.push_back(x.oz);
            dx.push_back(x.dx), dy.push_back(x.dy), dz.push_back(x.dz);
            tmin.push_back(x.tmin), tmax.push_back(x.tmax);
        }
        // Poisoned outputs: the stream must write every record.
        t.assign(r.size(), -1.f), u.assign(r.size(), -1.f), v.assign(r.size(), -1.f);
        id.assign(r.size(), 7u);
        occ.assign(r.size(), 9);
    }
    RayStream stream() const {
        return {ox.data(), oy.data(),   oz.data(),   dx.data(), dy.data(),
                dz.data(), tmin.data(), tmax.data(), ox.size()};
    }
    HitStream hits() { return {t.data(), u.data(), v.data(), id.data()}; }
};

bool same_float(float a, float b) {
    return std::memcmp(&a, &b, sizeof a) == 0;
}

void check_stream(const TriangleBvh& bvh, const TriangleMesh& mesh, const std::vector<Ray1>& rays,
                  StreamMode mode) {
    INFO("mode " << int(mode) << ", " << rays.size() << " rays");
    Columns c(rays);
    BvhCounters stream_closest, stream_any, single_closest, single_any;
    bvh.intersect_stream(c.stream(), c.hits(), &stream_closest, mode);
    bvh.occluded_stream(c.stream(), c.occ.data(), &stream_any, mode);
    std::size_t hits = 0, unstable = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        INFO("ray " << i);
        REQUIRE(c.occ[i] == uint8_t(bvh.occluded(rays[i], &single_any)));
        TriHit s;
        hits += bvh.intersect(rays[i], s, &single_closest);
        if (mode == StreamMode::SortedPackets) {
            // A packet tests triangles a single ray has culled, so where the single ray's or
            // the packet's hit is numerically unstable (test::geometric_hit) they may differ,
            // as they may against brute force (test_bvh.cpp). Occlusion is exact.
            const TriHit p{c.t[i], c.u[i], c.v[i], c.id[i]};
            if ((s.valid() && !test::geometric_hit(mesh, rays[i], s)) ||
                (p.valid() && !test::geometric_hit(mesh, rays[i], p))) {
                ++unstable;
                continue;
            }
        }
        REQUIRE(c.id[i] == s.id);
        REQUIRE(same_float(c.t[i], s.t));
        REQUIRE(same_float(c.u[i], s.u));
        REQUIRE(same_float(c.v[i], s.v));
    }
    if (mode == StreamMode::Interleaved) {
        // Every ray takes its single-ray steps.
        CHECK(unstable == 0);
        CHECK(stream_closest.nodes == single_closest.nodes);
        CHECK(stream_closest.leaves == single_closest.leaves);
        CHECK(stream_closest.blocks == single_closest.blocks);
        CHECK(stream_any.nodes == single_any.nodes);
        CHECK(stream_any.blocks == single_any.blocks);
    }
    CHECK(double(unstable) <= 0.01 * double(rays.size()) + 1.0);
    if (rays.size() > 100) CHECK(hits > 0);
}

// Rays the box test must survive: NaN, zero and tiny directions, empty intervals, axis-parallel
// rays in face planes, and rays through vertices.
std::vector<Ray1> awkward_rays(const TriangleMesh& m, std::size_t count) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> U(0.f, 1.f);
    const Bounds3 bb = m.bounds();
    const float nan = std::numeric_limits<float>::quiet_NaN();
    std::vector<Ray1> rays;
    for (std::size_t i = 0; i < count; ++i) {
        Vec3 a, b, c;
        m.corners(uint32_t(rng() % m.num_triangles()), a, b, c);
        const Vec3 o = bb.lo - bb.diagonal() * 0.1f;
        const Vec3 d = normalize(a - o);
        switch (i % 6) {
            case 0:
                rays.push_back({o.x, o.y, o.z, d.x, d.y, d.z, 0.f, kInf});  // through a vertex
                break;
            case 1:
                rays.push_back(
                    {a.x, a.y - 1.f, a.z, 0.f, 1.f, 0.f, 0.f, kInf});  // axis, face planes
                break;
            case 2:
                rays.push_back({o.x, o.y, o.z, nan, d.y, d.z, 0.f, kInf});
                break;
            case 3:
                rays.push_back({o.x, o.y, o.z, 0.f, 0.f, 0.f, 0.f, kInf});
                break;
            case 4:
                rays.push_back({o.x, o.y, o.z, d.x, d.y, d.z, 5.f, 1.f});  // tmin > tmax
                break;
            default:
                rays.push_back({o.x, o.y, o.z, d.x, 1e-30f, d.z, 0.f, U(rng) * 10.f});
                break;
        }
    }
    return rays;
}

}  // namespace

TEST_CASE("bvh streams equal single rays, ray for ray, in either mode", "[kernel][bvh]") {
    for (const char* name : {"bunny", "teapot", "cornell", "stadium", "dragon"}) {
        INFO(name);
        const bool big = std::string(name) == "dragon";
        const bench::KernelScene scene = bench::load_kernel_scene(name);
        const bench::RaySets sets = bench::make_ray_sets(scene, big ? 32 : 64, big ? 1024 : 4096);
        TriangleBvh bvh;
        bvh.build(scene.mesh.positions.data(), scene.mesh.indices.data(),
                  scene.mesh.num_triangles(), TriangleBvh::default_params());
        for (const auto mode : {StreamMode::Interleaved, StreamMode::SortedPackets}) {
            check_stream(bvh, scene.mesh, sets.primary, mode);
            check_stream(bvh, scene.mesh, sets.diffuse, mode);
            check_stream(bvh, scene.mesh, sets.shadow, mode);
            check_stream(bvh, scene.mesh, awkward_rays(scene.mesh, 600), mode);
        }
    }
}

TEST_CASE("bvh streams of any length, and over an empty tree", "[kernel][bvh]") {
    const bench::KernelScene scene = bench::load_kernel_scene("teapot");
    const bench::RaySets sets = bench::make_ray_sets(scene, 16, 64);
    TriangleBvh bvh;
    bvh.build(scene.mesh.positions.data(), scene.mesh.indices.data(), scene.mesh.num_triangles(),
              TriangleBvh::default_params());
    // Fewer rays than slots in flight, exactly as many, one more, none.
    for (std::size_t n : {std::size_t(0), std::size_t(1), std::size_t(3), std::size_t(8),
                          std::size_t(9), std::size_t(64)})
        for (const auto mode : {StreamMode::Interleaved, StreamMode::SortedPackets})
            check_stream(bvh, scene.mesh,
                         std::vector<Ray1>(sets.diffuse.begin(), sets.diffuse.begin() + long(n)),
                         mode);
    // A tree without triangles: every ray misses, records as the single-ray form leaves them.
    TriangleBvh empty;
    const float p[9] = {0, 0, 0, 1, 0, 0, 2, 0, 0};  // zero area: left out
    const uint32_t ix[3] = {0, 1, 2};
    empty.build(p, ix, 1, TriangleBvh::default_params());
    REQUIRE(empty.empty());
    for (const auto mode : {StreamMode::Interleaved, StreamMode::SortedPackets})
        check_stream(empty, scene.mesh, sets.diffuse, mode);
}
