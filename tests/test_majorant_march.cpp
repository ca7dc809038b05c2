// The majorant march kernel: SIMD against its scalar twin bit for bit, and the twin against
// the optical depth its collision point must have spent.
#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "engine/core/rng.h"
#include "kernels/majorant_march.h"

using namespace foton;

namespace {

struct Setup {
    std::vector<float> maj;
    kern::MajorantGrid g;
    Setup(int nx, int ny, int nz) {
        g.lo[0] = -1.f;
        g.lo[1] = -0.5f;
        g.lo[2] = -2.f;
        const float ext[3] = {2.f, 1.5f, 3.f};
        const int n[3] = {nx, ny, nz};
        for (int a = 0; a < 3; ++a) {
            g.res[a] = n[a];
            g.cell[a] = ext[a] / float(n[a]);
            g.inv_cell[a] = float(n[a]) / ext[a];
        }
        for (int i = 0; i < nx * ny * nz; ++i) {
            const float u = rng::uniform(1, 2, uint64_t(i), 0);
            maj.push_back(u < 0.3f ? 0.f : 4.f * u);  // empty cells too
        }
        g.majorant = maj.data();
    }
    float at(const float p[3]) const {
        int c[3];
        for (int a = 0; a < 3; ++a) {
            c[a] = int(std::floor((p[a] - g.lo[a]) * g.inv_cell[a]));
            if (c[a] < 0 || c[a] >= g.res[a]) return 0.f;
        }
        return maj[std::size_t((c[2] * g.res[1] + c[1]) * g.res[0] + c[0])];
    }
};

struct Flights {
    std::vector<float> ox, oy, oz, dx, dy, dz, t_end, tau, t, m;
    std::vector<uint8_t> hit;
    explicit Flights(std::size_t n) {
        for (auto* v : {&ox, &oy, &oz, &dx, &dy, &dz, &t_end, &tau, &t, &m}) v->resize(n);
        hit.resize(n);
    }
    kern::MarchFlights view() {
        return {ox.data(),    oy.data(),  oz.data(), dx.data(), dy.data(), dz.data(),
                t_end.data(), tau.data(), t.data(),  m.data(),  hit.data()};
    }
};

Flights random_flights(std::size_t n) {
    Flights f(n);
    for (std::size_t i = 0; i < n; ++i) {
        auto u = [&](int k) { return rng::uniform(2, 3, i, uint64_t(k)); };
        f.ox[i] = u(0) * 6.f - 3.f;
        f.oy[i] = u(1) * 6.f - 3.f;
        f.oz[i] = u(2) * 8.f - 4.f;
        // Towards a point of the grid's box, most of them.
        float d[3] = {u(3) * 2.f - 1.f - f.ox[i], u(4) * 1.5f - 0.5f - f.oy[i],
                      u(5) * 3.f - 2.f - f.oz[i]};
        if (i % 7 == 0) d[i % 3] = 0.f;  // axis-parallel flights
        const float len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        f.dx[i] = d[0] / len;
        f.dy[i] = d[1] / len;
        f.dz[i] = d[2] / len;
        f.t[i] = u(6) * 2.f;
        f.t_end[i] = i % 5 == 0 ? 1e30f : f.t[i] + u(7) * 10.f;
        f.tau[i] = -std::log1p(-u(8)) * 3.f;
    }
    return f;
}

}  // namespace

TEST_CASE("majorant march: the SIMD kernel equals its scalar twin bit for bit", "[media][fast]") {
    for (const int n : {1, 3, 16}) {
        const Setup s(n, n + 1, 2 * n);
        Flights a = random_flights(10007), b = a;
        kern::march_majorant(s.g, a.view(), a.t.size());
        kern::march_majorant_scalar(s.g, b.view(), b.t.size());
        std::size_t same = 0, hits = 0;
        for (std::size_t i = 0; i < a.t.size(); ++i) {
            same += (a.t[i] == b.t[i] && a.m[i] == b.m[i] && a.hit[i] == b.hit[i]) ? 1 : 0;
            hits += a.hit[i];
        }
        INFO("grid " << n << ": " << hits << " collisions");
        CHECK(same == a.t.size());
        CHECK(hits > 3000);
    }
}

TEST_CASE("majorant march: a collision spends exactly its optical depth", "[media][fast]") {
    const Setup s(5, 4, 7);
    Flights f = random_flights(2000);
    const Flights before = f;
    kern::march_majorant_scalar(s.g, f.view(), f.t.size());
    for (std::size_t i = 0; i < f.t.size(); ++i) {
        // The majorant integrated from the start to the result, by a fine midpoint rule.
        const float t0 = before.t[i];
        const float t1 = f.hit[i] ? f.t[i] : std::min(before.t_end[i], t0 + 20.f);
        const int steps = 4000;
        double tau = 0.0;
        for (int k = 0; k < steps; ++k) {
            const float t = t0 + (t1 - t0) * (k + 0.5f) / steps;
            const float p[3] = {before.ox[i] + t * before.dx[i], before.oy[i] + t * before.dy[i],
                                before.oz[i] + t * before.dz[i]};
            tau += s.at(p) * (t1 - t0) / steps;
        }
        INFO("flight " << i << " collided " << int(f.hit[i]));
        if (f.hit[i])
            CHECK(tau == Approx(before.tau[i]).margin(0.02 * (1.0 + before.tau[i])));
        else
            CHECK(tau < before.tau[i] + 0.02 * (1.0 + before.tau[i]));
    }
}
