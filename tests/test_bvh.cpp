// The wide BVH kernel (kernels/triangle_bvh.h): closest hits equal brute force exactly (t, id,
// u, v; ties go to the smaller id in both) on every ray of the benchmark ray sets and on
// degenerate, grazing and axis-parallel rays; any hit agrees with closest hit within tmax; the
// scalar twin (binary tree, scalar tests) agrees with both; every node/leaf shape the benchmarks
// use gives the same answers; bad input builds a valid tree without the bad triangles.
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>

#include "bench/ray_sets.h"
#include "brute_oracle.h"
#include "kernels/triangle_bvh.h"
#include "test_util.h"

using namespace foton;
using namespace foton::kern;

namespace {

template <class Bvh>
Bvh bvh_of(const TriangleMesh& m, bool twin = true) {
    Bvh b;
    b.build(m.positions.data(), m.indices.data(), m.num_triangles(), Bvh::default_params(), twin);
    return b;
}

// Brute force that breaks exact ties in t by the smaller id, like the BVH (the SIMD brute
// oracle keeps the first of equal hits in id order, which is the same thing).
bool brute_closest(const test::BruteOracle& b, const Ray1& r, TriHit& h) {
    return b.closest(r, h);
}

// Rays that stress the box test: along the axes, through vertices and edges, grazing faces,
// with zero direction components, starting on a box face, and with tiny or NaN directions.
std::vector<Ray1> edge_case_rays(const TriangleMesh& m, std::size_t count, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> U(0.f, 1.f);
    const Bounds3 bb = m.bounds();
    const Vec3 ext = bb.diagonal();
    std::vector<Ray1> rays;
    const std::size_t nt = m.num_triangles();
    for (std::size_t i = 0; i < count; ++i) {
        Vec3 p0, p1, p2;
        m.corners(uint32_t(rng() % nt), p0, p1, p2);
        Vec3 target;
        switch (i % 4) {
            case 0:
                target = p0;
                break;  // a vertex
            case 1:
                target = p0 + (p1 - p0) * U(rng);
                break;  // an edge
            case 2:
                target = (p0 + p1 + p2) * (1.f / 3.f);
                break;
            default:
                target = p1 + (p2 - p1) * 0.5f;
                break;
        }
        const int axis = int(rng() % 3);
        Vec3 d{0.f, 0.f, 0.f};
        switch ((i / 4) % 5) {
            case 0:
                d[axis] = rng() % 2 ? 1.f : -1.f;
                break;  // axis-parallel
            case 1: {   // in an axis plane
                d[axis] = 0.f;
                d[(axis + 1) % 3] = U(rng) - 0.5f;
                d[(axis + 2) % 3] = U(rng) - 0.5f;
                break;
            }
            case 2:
                d = normalize(p1 - p0);
                break;  // along an edge (grazing)
            case 3:
                d = normalize(Vec3{U(rng) - 0.5f, U(rng) - 0.5f, U(rng) - 0.5f});
                break;
            default:
                d = Vec3{1e-20f, U(rng) - 0.5f, 0.f};
                break;  // tiny component
        }
        if (d.x == 0.f && d.y == 0.f && d.z == 0.f) d = Vec3{0.f, 1.f, 0.f};
        // Start on the far side so the ray passes the target, or exactly on the bounds.
        const float back = length(ext);
        Vec3 o = target - d * back;
        if (i % 7 == 0) o[axis] = d[axis] >= 0.f ? bb.lo[axis] : bb.hi[axis];
        const float tmax = (i % 11 == 0) ? back : kInf;
        rays.push_back({o.x, o.y, o.z, d.x, d.y, d.z, 0.f, tmax});
    }
    // Degenerate rays: zero direction, NaN direction, empty interval.
    const Vec3 c = bb.center();
    rays.push_back({c.x, c.y, c.z, 0.f, 0.f, 0.f, 0.f, kInf});
    const float nan = std::numeric_limits<float>::quiet_NaN();
    rays.push_back({c.x, c.y, c.z, nan, 1.f, 0.f, 0.f, kInf});
    rays.push_back({c.x, c.y, c.z, 0.f, 1.f, 0.f, 1.f, 0.5f});
    return rays;
}

// Checks every ray; returns the number of hits.
template <class Bvh>
std::size_t check_rays(const Bvh& bvh, const test::BruteOracle& brute, const TriangleMesh& mesh,
                       const std::vector<Ray1>& rays, bool twin, double max_unstable = 0.005) {
    std::size_t hits = 0, unstable = 0;
    for (std::size_t i = 0; i < rays.size(); i += test::kSanitizedStride) {
        const Ray1& r = rays[i];
        INFO(std::hexfloat << "ray " << i << ": o " << r.ox << " " << r.oy << " " << r.oz << " d "
                           << r.dx << " " << r.dy << " " << r.dz << " tmax " << r.tmax);
        TriHit hb, hv;
        const bool b = brute_closest(brute, r, hb);
        if (b && !test::geometric_hit(mesh, r, hb)) {
            ++unstable;
            continue;
        }
        REQUIRE(bvh.intersect(r, hv) == b);
        REQUIRE(bvh.occluded(r) == b);
        if (twin) {
            TriHit hs;
            REQUIRE(bvh.intersect_scalar(r, hs) == b);
            REQUIRE(bvh.occluded_scalar(r) == b);
            if (b) {
                REQUIRE(hs.t == hb.t);
                REQUIRE(hs.id == hb.id);
            }
        }
        if (!b) continue;
        ++hits;
        REQUIRE(hv.t == hb.t);
        REQUIRE(hv.id == hb.id);
        REQUIRE(hv.u == hb.u);
        REQUIRE(hv.v == hb.v);
        // Any hit within a tmax just short of / just past the hit.
        Ray1 shorter = r;
        shorter.tmax = hb.t;
        TriHit hshort;
        REQUIRE(bvh.occluded(shorter) == brute_closest(brute, shorter, hshort));
    }
    CHECK(double(unstable) <= max_unstable * double(rays.size()));
    return hits;
}

}  // namespace

TEST_CASE("bvh equals brute force on every ray of the benchmark ray sets", "[kernel][bvh]") {
    for (const char* name : {"bunny", "teapot", "cornell", "stadium", "dragon"}) {
        INFO(name);
        const bool big = std::string(name) == "dragon";
        const bench::KernelScene scene = bench::load_kernel_scene(name);
        const bench::RaySets sets = bench::make_ray_sets(scene, big ? 32 : 64, big ? 512 : 2048);
        const TriangleBvh bvh = bvh_of<TriangleBvh>(scene.mesh, !big);
        const test::BruteOracle brute(scene.mesh);
        CHECK(bvh.stats().triangles + bvh.stats().skipped == scene.mesh.num_triangles());
        const std::size_t hits = check_rays(bvh, brute, scene.mesh, sets.primary, !big) +
                                 check_rays(bvh, brute, scene.mesh, sets.diffuse, !big);
        std::size_t blocked = 0;
        for (std::size_t i = 0; i < sets.shadow.size(); i += test::kSanitizedStride) {
            const Ray1& r = sets.shadow[i];
            TriHit hb;
            const bool b = brute.closest(r, hb);
            REQUIRE(bvh.occluded(r) == b);
            blocked += b;
        }
        CHECK(hits > sets.primary.size() / 20 / test::kSanitizedStride);
        CHECK(blocked > 0);
        // A fifth of these graze an edge on purpose: up to 5 % may be unstable hits.
        if (!big) {
            const auto edge = edge_case_rays(scene.mesh, 4000, 3);
            CHECK(check_rays(bvh, brute, scene.mesh, edge, true, 0.05) >
                  edge.size() / 4 / test::kSanitizedStride);
        }
    }
}

TEST_CASE("every bvh shape gives the same hits", "[kernel][bvh]") {
    const bench::KernelScene scene = bench::load_kernel_scene("bunny");
    const bench::RaySets sets = bench::make_ray_sets(scene, 32, 1024);
    const test::BruteOracle brute(scene.mesh);
    const auto b44 = bvh_of<TriangleBvhT<4, 4>>(scene.mesh);
    check_rays(b44, brute, scene.mesh, sets.diffuse, true);
#if defined(__AVX__)
    check_rays(bvh_of<TriangleBvhT<8, 4>>(scene.mesh), brute, scene.mesh, sets.diffuse, true);
#endif
#if defined(__AVX512BW__)
    check_rays(bvh_of<TriangleBvhT<16, 4>>(scene.mesh), brute, scene.mesh, sets.diffuse, true);
    check_rays(bvh_of<TriangleBvhT<16, 8>>(scene.mesh), brute, scene.mesh, sets.primary, true);
#endif
}

TEST_CASE("bvh breaks exact ties by the smaller id", "[kernel][bvh]") {
    // Two coincident triangles (ids 0 and 2) and a third behind them; the ray hits the pair.
    const float pos[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, -1, 1, 0, -1, 0, 1, -1};
    const uint32_t idx[] = {0, 1, 2, 3, 4, 5, 0, 1, 2};
    TriangleBvh bvh;
    bvh.build(pos, idx, 3, TriangleBvh::default_params(), true);
    const Ray1 r{0.25f, 0.25f, 1.f, 0.f, 0.f, -1.f, 0.f, kInf};
    TriHit h, hs;
    REQUIRE(bvh.intersect(r, h));
    CHECK(h.id == 0);
    CHECK(h.t == 1.f);
    REQUIRE(bvh.intersect_scalar(r, hs));
    CHECK(hs.id == 0);
    // tmax is exclusive: a hit exactly at tmax is no hit, tie or not.
    const Ray1 r2{0.25f, 0.25f, 1.f, 0.f, 0.f, -1.f, 0.f, 1.f};
    TriHit h2;
    CHECK_FALSE(bvh.intersect(r2, h2));
    CHECK_FALSE(bvh.occluded(r2));
}

TEST_CASE("bad bvh input builds a valid tree without the bad triangles", "[kernel][bvh]") {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float inf = std::numeric_limits<float>::infinity();
    // 0: good; 1: NaN vertex; 2: zero area (repeated vertex); 3: collinear; 4: Inf vertex;
    // 5: good.
    const float pos[] = {0,   0, 0, 1, 0, 0, 0, 1, 0,   // 0 1 2
                         nan, 0, 0,                     // 3
                         2,   0, 0, 3, 0, 0,            // 4 5 (collinear with 1)
                         inf, 1, 1,                     // 6
                         0,   0, 2, 1, 0, 2, 0, 1, 2};  // 7 8 9
    const uint32_t idx[] = {0, 1, 2, 3, 1, 2, 0, 0, 2, 1, 4, 5, 6, 1, 2, 7, 8, 9};
    TriangleBvh bvh;
    bvh.build(pos, idx, 6, TriangleBvh::default_params(), true);
    CHECK(bvh.stats().triangles == 2);
    CHECK(bvh.stats().skipped == 4);
    TriHit h;
    REQUIRE(bvh.intersect({0.2f, 0.2f, 5.f, 0.f, 0.f, -1.f, 0.f, kInf}, h));
    CHECK(h.id == 5);
    CHECK(h.t == 3.f);
    TriHit h2;
    REQUIRE(bvh.intersect({0.2f, 0.2f, 1.f, 0.f, 0.f, -1.f, 0.f, kInf}, h2));
    CHECK(h2.id == 0);

    TriangleBvh empty;
    empty.build(pos, idx, 0, TriangleBvh::default_params());
    CHECK(empty.empty());
    TriHit h3;
    CHECK_FALSE(empty.intersect({0, 0, 5, 0, 0, -1, 0, kInf}, h3));
    CHECK_FALSE(empty.occluded({0, 0, 5, 0, 0, -1, 0, kInf}));
    // Only bad triangles: also empty.
    TriangleBvh bad;
    bad.build(pos, idx + 3, 1, TriangleBvh::default_params());
    CHECK(bad.empty());
}

TEST_CASE("bvh build is the same for any parallelism", "[kernel][bvh]") {
    const bench::KernelScene scene = bench::load_kernel_scene("bunny");
    const TriangleMesh& m = scene.mesh;
    auto p1 = TriangleBvh::default_params();
    auto p2 = p1;
    p2.parallel_grain = 64;
    // A fake "parallel" invoke that runs the second job first: the tree must not care.
    p2.parallel = [](const std::function<void()>& a, const std::function<void()>& b) {
        b();
        a();
    };
    TriangleBvh a, b;
    a.build(m.positions.data(), m.indices.data(), m.num_triangles(), p1);
    b.build(m.positions.data(), m.indices.data(), m.num_triangles(), p2);
    REQUIRE(a.nodes().size() == b.nodes().size());
    REQUIRE(a.blocks().size() == b.blocks().size());
    CHECK(std::memcmp(a.nodes().data(), b.nodes().data(),
                      a.nodes().size() * sizeof(a.nodes()[0])) == 0);
    CHECK(std::memcmp(a.blocks().data(), b.blocks().data(),
                      a.blocks().size() * sizeof(a.blocks()[0])) == 0);
    CHECK(a.stats().sah_wide == b.stats().sah_wide);
    CHECK(a.stats().sah_wide > 0.0);
}

namespace {

// Runs `rays` through the packet forms, W consecutive rays per packet (a random subset of them
// active), and requires of every active ray exactly what the single-ray forms give it. Rays
// whose brute-force hit is numerically unstable (see geometric_hit) are skipped: the packet
// tests more triangles than the single ray culls to, and may see such a hit where it does not.
// With expect_packets (coherent rays) the packets must also have done their job: at most 2/3
// of the nodes the rays visit one by one (had every ray fallen back to the single-ray path, it
// would be as many or more; measured 0.08x to 0.6x, the dragon's 32 x 32 rays the least
// coherent).
template <class Bvh>
void check_packets(const Bvh& bvh, const test::BruteOracle& brute, const TriangleMesh& mesh,
                   const std::vector<Ray1>& rays, uint32_t seed, bool expect_packets = false) {
    BvhCounters packet_counts, single_counts;
    constexpr std::size_t W = kBlockWidth;
    std::mt19937 rng(seed);
    for (std::size_t first = 0; first < rays.size(); first += W) {
        RayPacket p;
        PacketHits h;
        float tmax[W];
        uint32_t active = 0;
        const uint32_t subset = (first / W) % 3 == 0 ? uint32_t(rng()) : ~0u;
        for (std::size_t i = 0; i < W; ++i) {
            const Ray1& r = rays[std::min(first + i, rays.size() - 1)];
            p.ox[i] = r.ox, p.oy[i] = r.oy, p.oz[i] = r.oz;
            p.dx[i] = r.dx, p.dy[i] = r.dy, p.dz[i] = r.dz;
            p.tmin[i] = r.tmin;
            tmax[i] = h.t[i] = r.tmax;
            h.u[i] = h.v[i] = 0.f;
            h.id[i] = kInvalidId;
            if (first + i < rays.size() && ((subset >> i) & 1u)) active |= 1u << i;
        }
        bvh.intersect_packet(p, active, h, &packet_counts);
        const uint32_t occ = bvh.occluded_packet(p, tmax, active);
        for (std::size_t i = 0; i < W; ++i) {
            const Ray1& r = rays[std::min(first + i, rays.size() - 1)];
            INFO("ray " << first + i);
            if (!((active >> i) & 1u)) {
                REQUIRE(h.id[i] == kInvalidId);
                REQUIRE(((occ >> i) & 1u) == 0);
                continue;
            }
            TriHit s, b;
            if (brute.closest(r, b) && !test::geometric_hit(mesh, r, b)) continue;
            const bool hit = bvh.intersect(r, s, &single_counts);
            REQUIRE((h.id[i] != kInvalidId) == hit);
            REQUIRE(bool((occ >> i) & 1u) == bvh.occluded(r));
            if (!hit) continue;
            REQUIRE(h.t[i] == s.t);
            REQUIRE(h.id[i] == s.id);
            REQUIRE(h.u[i] == s.u);
            REQUIRE(h.v[i] == s.v);
        }
    }
    INFO("nodes: packets " << packet_counts.nodes << ", rays one by one " << single_counts.nodes);
    if (expect_packets) CHECK(3 * packet_counts.nodes < 2 * single_counts.nodes);
}

}  // namespace

TEST_CASE("bvh packets equal single rays, ray for ray", "[kernel][bvh]") {
    for (const char* name : {"bunny", "teapot", "cornell", "stadium", "dragon"}) {
        INFO(name);
        const bool big = std::string(name) == "dragon";
        const bench::KernelScene scene = bench::load_kernel_scene(name);
        const bench::RaySets sets = bench::make_ray_sets(scene, big ? 32 : 64, big ? 512 : 2048);
        const TriangleBvh bvh = bvh_of<TriangleBvh>(scene.mesh, false);
        const test::BruteOracle brute(scene.mesh);
        check_packets(bvh, brute, scene.mesh, sets.primary, 1, true);
        check_packets(bvh, brute, scene.mesh, sets.diffuse, 2);
        check_packets(bvh, brute, scene.mesh, sets.shadow, 3);
        // Mixed octants, zero and NaN components, rays in face planes: the fallback lanes.
        if (!big) check_packets(bvh, brute, scene.mesh, edge_case_rays(scene.mesh, 2000, 4), 4);
    }
    // A packet that already has hits: only closer (or tied, smaller id) ones replace them.
    const bench::KernelScene scene = bench::load_kernel_scene("bunny");
    const bench::RaySets sets = bench::make_ray_sets(scene, 32, 64);
    const TriangleBvh bvh = bvh_of<TriangleBvh>(scene.mesh, false);
    RayPacket p;
    PacketHits h;
    TriHit want[kBlockWidth];
    for (std::size_t i = 0; i < kBlockWidth; ++i) {
        const Ray1& r = sets.primary[200 + i];
        p.ox[i] = r.ox, p.oy[i] = r.oy, p.oz[i] = r.oz;
        p.dx[i] = r.dx, p.dy[i] = r.dy, p.dz[i] = r.dz;
        p.tmin[i] = r.tmin;
        TriHit s;
        bvh.intersect(r, s);
        // Half the rays carry a fake earlier hit just before the true one.
        h.t[i] = (i % 2 && s.valid()) ? s.t * 0.5f : r.tmax;
        h.id[i] = (i % 2 && s.valid()) ? 12345u : kInvalidId;
        h.u[i] = h.v[i] = 0.25f;
        want[i] = (i % 2 && s.valid()) ? TriHit{h.t[i], 0.25f, 0.25f, 12345u} : s;
    }
    bvh.intersect_packet(p, ~0u >> (32 - kBlockWidth), h);
    for (std::size_t i = 0; i < kBlockWidth; ++i) {
        CHECK(h.t[i] == want[i].t);
        CHECK(h.id[i] == want[i].id);
        if (want[i].valid()) CHECK(h.u[i] == want[i].u);
    }
}

TEST_CASE("next_up is nextafter towards +inf", "[kernel][bvh]") {
    std::mt19937 rng(9);
    std::vector<float> xs = {0.f,
                             -0.f,
                             1.f,
                             -1.f,
                             0x1p-149f,
                             -0x1p-149f,
                             0x1p-126f,
                             std::numeric_limits<float>::max(),
                             -std::numeric_limits<float>::max(),
                             kInf,
                             -kInf};
    for (int i = 0; i < 100000; ++i) {
        const uint32_t b = uint32_t(rng());
        float f;
        std::memcpy(&f, &b, sizeof f);
        if (!std::isnan(f)) xs.push_back(f);
    }
    for (float x : xs) {
        INFO(std::hexfloat << x);
        const float a = bvh_detail::next_up(x), b = std::nextafter(x, kInf);
        REQUIRE(std::memcmp(&a, &b, sizeof a) == 0);
    }
    CHECK(std::isnan(bvh_detail::next_up(std::numeric_limits<float>::quiet_NaN())));
}

TEST_CASE("the tree's large arrays start on 2 MB boundaries, small ones on cache lines",
          "[kernel][bvh]") {
    // madvise(MADV_HUGEPAGE) applies to whole 2 MB pages: an array that did not start on one
    // would keep its first and last megabytes on 4 KB pages (kernels/huge_page_allocator.h).
    HugePageAllocator<float> alloc;
    for (const std::size_t floats : {std::size_t(16), std::size_t(1000), std::size_t(1) << 19,
                                     (std::size_t(3) << 20) / 4 + 7}) {
        float* p = alloc.allocate(floats);
        const auto at = reinterpret_cast<std::uintptr_t>(p);
        const bool large = floats * sizeof(float) >= kHugePageBytes;
        INFO(floats << " floats at " << at);
        CHECK(at % (large ? kHugePageBytes : 64) == 0);
        p[0] = 1.f;
        p[floats - 1] = 2.f;  // the whole range is ours (ASan checks it in the sanitizer build)
        alloc.deallocate(p, floats);
    }
    // The bunny's leaf blocks (4 MB) are such an array.
    const bench::KernelScene scene = bench::load_kernel_scene("bunny");
    const TriangleBvh bvh = bvh_of<TriangleBvh>(scene.mesh, false);
    REQUIRE(bvh.blocks().size() * sizeof(bvh.blocks()[0]) >= kHugePageBytes);
    CHECK(reinterpret_cast<std::uintptr_t>(bvh.blocks().data()) % kHugePageBytes == 0);
}
