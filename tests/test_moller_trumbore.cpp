// Möller–Trumbore: hand-computed cases, and the SIMD kernels against their scalar twin on a
// million random rays including degenerate, parallel and grazing ones.
#include <catch2/catch.hpp>
#include <random>

#include "kernels/moller_trumbore.h"

using namespace foton::kern;

namespace {
Ray1 ray(float ox, float oy, float oz, float dx, float dy, float dz, float tmax = kInf) {
    return {ox, oy, oz, dx, dy, dz, 0.f, tmax};
}
// The unit right triangle (0,0,0), (1,0,0), (0,1,0) in the z = 0 plane.
bool hit_unit(const Ray1& r, float& t, float& u, float& v) {
    return intersect_triangle_scalar(r, 0, 0, 0, 1, 0, 0, 0, 1, 0, r.tmax, t, u, v);
}
}  // namespace

TEST_CASE("Möller–Trumbore: hits, misses, edges and parallel rays", "[kernel][mt]") {
    float t, u, v;
    SECTION("perpendicular hit with known barycentrics") {
        REQUIRE(hit_unit(ray(0.25f, 0.5f, 2.f, 0, 0, -1), t, u, v));
        CHECK(t == Approx(2.f));
        CHECK(u == Approx(0.25f));
        CHECK(v == Approx(0.5f));
    }
    SECTION("hit from behind (no culling)") {
        REQUIRE(hit_unit(ray(0.1f, 0.1f, -3.f, 0, 0, 1), t, u, v));
        CHECK(t == Approx(3.f));
    }
    SECTION("oblique hit") {
        // From (1, 1, 1) towards (0.25, 0.25, 0): t = |d| scaled, d unnormalised here.
        REQUIRE(hit_unit(ray(1.f, 1.f, 1.f, -0.75f, -0.75f, -1.f), t, u, v));
        CHECK(t == Approx(1.f));
        CHECK(u == Approx(0.25f));
        CHECK(v == Approx(0.25f));
    }
    SECTION("misses outside each edge") {
        CHECK_FALSE(hit_unit(ray(-0.1f, 0.5f, 1.f, 0, 0, -1), t, u, v));
        CHECK_FALSE(hit_unit(ray(0.5f, -0.1f, 1.f, 0, 0, -1), t, u, v));
        CHECK_FALSE(hit_unit(ray(0.6f, 0.6f, 1.f, 0, 0, -1), t, u, v));
    }
    SECTION("edges and corners count as hits") {
        CHECK(hit_unit(ray(0.f, 0.5f, 1.f, 0, 0, -1), t, u, v));   // u = 0
        CHECK(hit_unit(ray(0.5f, 0.f, 1.f, 0, 0, -1), t, u, v));   // v = 0
        CHECK(hit_unit(ray(0.5f, 0.5f, 1.f, 0, 0, -1), t, u, v));  // u + v = 1
        CHECK(hit_unit(ray(0.f, 0.f, 1.f, 0, 0, -1), t, u, v));    // corner
    }
    SECTION("parallel rays miss, in and off the plane") {
        CHECK_FALSE(hit_unit(ray(0.2f, 0.2f, 1.f, 1, 0, 0), t, u, v));
        CHECK_FALSE(hit_unit(ray(-1.f, 0.2f, 0.f, 1, 0, 0), t, u, v));
    }
    SECTION("t range is open: tmin < t < tmax") {
        CHECK_FALSE(hit_unit(ray(0.2f, 0.2f, 1.f, 0, 0, -1, 1.f), t, u, v));
        CHECK(hit_unit(ray(0.2f, 0.2f, 1.f, 0, 0, -1, 1.0001f), t, u, v));
        CHECK_FALSE(hit_unit(ray(0.2f, 0.2f, -1.f, 0, 0, -1), t, u, v));  // behind the origin
    }
    SECTION("degenerate triangle never hits") {
        CHECK_FALSE(intersect_triangle_scalar(ray(0.2f, 0.f, 1.f, 0, 0, -1), 0, 0, 0, 1, 0, 0, 2, 0,
                                              0, kInf, t, u, v));
    }
}

namespace {
// Random triangles of mixed shapes: ordinary, slivers, degenerate (zero edge / collinear).
void random_block(std::mt19937& rng, TriangleBlock& b, uint32_t base_id) {
    std::uniform_real_distribution<float> U(-1.f, 1.f);
    std::uniform_int_distribution<int> kind(0, 9);
    b.clear();
    for (std::size_t l = 0; l < kBlockWidth; ++l) {
        float p0[3] = {U(rng), U(rng), U(rng)}, p1[3], p2[3];
        const int k = kind(rng);
        for (int a = 0; a < 3; ++a) {
            p1[a] = p0[a] + U(rng);
            p2[a] = p0[a] + U(rng);
        }
        if (k == 0)
            for (int a = 0; a < 3; ++a) p2[a] = p1[a];  // zero edge
        if (k == 1)
            for (int a = 0; a < 3; ++a) p2[a] = p0[a] + 2.f * (p1[a] - p0[a]);  // collinear
        if (k == 2)
            for (int a = 0; a < 3; ++a) p2[a] = p1[a] + 1e-4f * U(rng);  // sliver
        if (k == 3) p1[2] = p2[2] = p0[2];                               // axis-aligned
        b.set(l, p0, p1, p2, base_id + uint32_t(l));
    }
}

Ray1 random_ray(std::mt19937& rng, const TriangleBlock& b) {
    std::uniform_real_distribution<float> U(-1.f, 1.f);
    std::uniform_int_distribution<int> kind(0, 4);
    Ray1 r{U(rng) * 2, U(rng) * 2, U(rng) * 2, U(rng), U(rng), U(rng), 0.f, kInf};
    const int k = kind(rng);
    const std::size_t l = std::size_t(std::uniform_int_distribution<int>(0, kBlockWidth - 1)(rng));
    if (k == 0) {
        // Aim at a point of a triangle's edge: the edge cases.
        const float s = std::uniform_real_distribution<float>(0.f, 1.f)(rng);
        const float tx = b.v0x[l] + s * b.e1x[l], ty = b.v0y[l] + s * b.e1y[l],
                    tz = b.v0z[l] + s * b.e1z[l];
        r.dx = tx - r.ox;
        r.dy = ty - r.oy;
        r.dz = tz - r.oz;
    } else if (k == 1) {
        // Grazing: direction (almost) in a triangle's plane.
        const float e1[3] = {b.e1x[l], b.e1y[l], b.e1z[l]}, e2[3] = {b.e2x[l], b.e2y[l], b.e2z[l]};
        const float s = U(rng), w = 1e-3f * U(rng);
        r.dx = e1[0] + s * e2[0] + w;
        r.dy = e1[1] + s * e2[1];
        r.dz = e1[2] + s * e2[2];
        r.ox = b.v0x[l] - 0.5f * r.dx;
        r.oy = b.v0y[l] - 0.5f * r.dy;
        r.oz = b.v0z[l] - 0.5f * r.dz;
    } else if (k == 2) {
        r.tmax = std::uniform_real_distribution<float>(0.f, 3.f)(rng);
    }
    return r;
}
}  // namespace

TEST_CASE("SIMD triangle block agrees with its scalar twin on 1M rays", "[kernel][mt]") {
    std::mt19937 rng(1234);
    TriangleBlock b;
    std::size_t hits = 0, total = 0;
    const std::size_t rays = std::size_t(1) << 20;
    const std::size_t per_block = 64;
    for (std::size_t i = 0; i < rays / per_block; ++i) {
        random_block(rng, b, uint32_t(i * kBlockWidth));
        for (std::size_t j = 0; j < per_block; ++j, ++total) {
            const Ray1 r = random_ray(rng, b);
            TriHit hs, hv;
            hs.t = hv.t = r.tmax;
            const bool s = intersect_block_scalar(r, b, hs);
            const bool v = intersect_block(r, b, hv);
            REQUIRE(s == v);
            REQUIRE(occluded_block(r, b) == s);
            REQUIRE(occluded_block_scalar(r, b) == s);
            if (s) {
                ++hits;
                REQUIRE(hs.id == hv.id);
                REQUIRE(hs.t == hv.t);  // same arithmetic: bit-identical, not just within 1e-5
                REQUIRE(hs.u == hv.u);
                REQUIRE(hs.v == hv.v);
            }
        }
    }
    // The ray set must exercise both outcomes substantially.
    CHECK(hits > total / 20);
    CHECK(hits < total * 19 / 20);
}

TEST_CASE("ray packet against one triangle agrees with the scalar twin", "[kernel][mt]") {
    std::mt19937 rng(99);
    TriangleBlock b;
    std::size_t hits = 0;
    for (int iter = 0; iter < 20000; ++iter) {
        random_block(rng, b, 0);
        const std::size_t lane = std::size_t(iter) % kBlockWidth;
        RayPacket p;
        PacketHits h;
        Ray1 rs[kBlockWidth];
        for (std::size_t l = 0; l < kBlockWidth; ++l) {
            rs[l] = random_ray(rng, b);
            p.ox[l] = rs[l].ox;
            p.oy[l] = rs[l].oy;
            p.oz[l] = rs[l].oz;
            p.dx[l] = rs[l].dx;
            p.dy[l] = rs[l].dy;
            p.dz[l] = rs[l].dz;
            p.tmin[l] = rs[l].tmin;
            h.t[l] = rs[l].tmax;
            h.u[l] = h.v[l] = 0.f;
            h.id[l] = kInvalidId;
        }
        const uint32_t mask = intersect_packet(p, b, lane, h);
        for (std::size_t l = 0; l < kBlockWidth; ++l) {
            float t, u, v;
            const bool s = intersect_triangle_scalar(
                rs[l], b.v0x[lane], b.v0y[lane], b.v0z[lane], b.e1x[lane], b.e1y[lane], b.e1z[lane],
                b.e2x[lane], b.e2y[lane], b.e2z[lane], rs[l].tmax, t, u, v);
            REQUIRE(bool(mask >> l & 1u) == s);
            if (s) {
                ++hits;
                REQUIRE(h.t[l] == t);
                REQUIRE(h.u[l] == u);
                REQUIRE(h.v[l] == v);
                REQUIRE(h.id[l] == b.id[lane]);
            } else {
                REQUIRE(h.id[l] == kInvalidId);
            }
        }
    }
    CHECK(hits > 1000);
}
