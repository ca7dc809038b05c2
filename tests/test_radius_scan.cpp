// The merge grid's bucket scan (kernels/radius_scan.h) and the grid over it
// (engine/transport/bidir/vertex_grid.h): the SIMD scan visits exactly the points its scalar
// twin visits, in the same order, and a grid query finds exactly the vertices a brute-force
// search finds, with the SIMD scan and without.
#include <algorithm>
#include <catch2/catch.hpp>
#include <random>
#include <vector>

#include "engine/transport/bidir/vertex_grid.h"
#include "kernels/radius_scan.h"
#include "kernels/simd.h"

using namespace foton;

TEST_CASE("Radius scan: SIMD visits what its scalar twin visits, in order", "[kernel][fast]") {
    std::mt19937 g(3);
    std::uniform_real_distribution<float> u(-1.f, 1.f);
    const std::size_t n = 1000;
    std::vector<float> x(n + simd::kWidth), y(n + simd::kWidth), z(n + simd::kWidth);
    for (std::size_t i = 0; i < n; ++i) x[i] = u(g), y[i] = u(g), z[i] = u(g);
    // A point exactly on the sphere's surface.
    x[7] = 0.5f, y[7] = 0.f, z[7] = 0.f;
    std::size_t found = 0;
    for (int k = 0; k < 300; ++k) {
        const float q[3] = {k == 0 ? 0.f : u(g), k == 0 ? 0.f : u(g), k == 0 ? 0.f : u(g)};
        const uint32_t begin = uint32_t(k % 37),
                       end = uint32_t(std::min<std::size_t>(n, begin + 3 + k * 3));
        const float r2 = 0.25f;
        std::vector<uint32_t> a, b;
        kern::radius_scan(x.data(), y.data(), z.data(), begin, end, q, r2,
                          [&](uint32_t i) { a.push_back(i); });
        kern::radius_scan_scalar(x.data(), y.data(), z.data(), begin, end, q, r2,
                                 [&](uint32_t i) { b.push_back(i); });
        CHECK(a == b);
        found += a.size();
        if (k == 0 && begin <= 7 && 7 < end) CHECK(std::count(a.begin(), a.end(), 7u) == 1);
    }
    CHECK(found > 1000);
}

TEST_CASE("Vertex grid: a query finds exactly the vertices within the radius", "[kernel][fast]") {
    std::mt19937 g(4);
    std::uniform_real_distribution<float> u(0.f, 10.f);
    LightVertices v;
    const std::size_t n = 5000;
    v.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        v.px[i] = u(g);
        v.py[i] = i % 3 == 0 ? 0.f : u(g);  // a third on a wall, as vertices lie on surfaces
        v.pz[i] = u(g);
    }
    const float r = 0.4f;
    for (const bool simd : {true, false}) {
        VertexGrid grid;
        grid.build(v, r, simd);
        std::size_t found = 0;
        for (int k = 0; k < 200; ++k) {
            const Vec3 p{u(g), k % 2 ? 0.1f : u(g), u(g)};
            std::vector<uint32_t> got, want;
            grid.query(p, [&](uint32_t i) { got.push_back(i); });
            for (uint32_t i = 0; i < n; ++i) {
                const float ex = v.px[i] - p.x, ey = v.py[i] - p.y, ez = v.pz[i] - p.z;
                if ((ex * ex + ey * ey) + ez * ez <= r * r) want.push_back(i);
            }
            std::sort(got.begin(), got.end());
            CHECK(got == want);
            found += got.size();
        }
        CHECK(found > 200);
    }
}
