// Google Benchmark: the majorant march (kernels/majorant_march.h) against its scalar twin:
// 4,096 flights through a 16^3 majorant grid of a cloud (a ball of density with empty
// corners), each spending one optical depth drawn as delta tracking draws it (flights per
// second). What the SIMD DDA saves per tentative collision, without the density lookups and
// collision choices around it.
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>
#include <vector>

#include "kernels/majorant_march.h"

using namespace foton::kern;

namespace {

constexpr std::size_t kFlights = 4096;

struct MarchSetup {
    std::vector<float> maj;
    MajorantGrid g{};
    std::vector<float> ox, oy, oz, dx, dy, dz, t_end, tau, t, t0, m;
    std::vector<uint8_t> hit;
    MarchSetup() {
        const int n = 16;
        for (int a = 0; a < 3; ++a) {
            g.lo[a] = -1.f;
            g.res[a] = n;
            g.cell[a] = 2.f / n;
            g.inv_cell[a] = n / 2.f;
        }
        for (int z = 0; z < n; ++z)
            for (int y = 0; y < n; ++y)
                for (int x = 0; x < n; ++x) {
                    const float fx = (x + 0.5f) / n - 0.5f, fy = (y + 0.5f) / n - 0.5f,
                                fz = (z + 0.5f) / n - 0.5f;
                    maj.push_back(std::max(0.f, 1.f - 4.f * (fx * fx + fy * fy + fz * fz)));
                }
        g.majorant = maj.data();
        g.scale = 2.f;
        std::mt19937 r(3);
        std::uniform_real_distribution<float> u(0.f, 1.f);
        for (std::size_t i = 0; i < kFlights; ++i) {
            // From a sphere of radius 2 around the cloud towards a point inside it.
            const float a = 6.2831853f * u(r), b = std::acos(2.f * u(r) - 1.f);
            const float px = 2.f * std::sin(b) * std::cos(a), py = 2.f * std::sin(b) * std::sin(a),
                        pz = 2.f * std::cos(b);
            float qx = u(r) - 0.5f - px, qy = u(r) - 0.5f - py, qz = u(r) - 0.5f - pz;
            const float len = std::sqrt(qx * qx + qy * qy + qz * qz);
            ox.push_back(px);
            oy.push_back(py);
            oz.push_back(pz);
            dx.push_back(qx / len);
            dy.push_back(qy / len);
            dz.push_back(qz / len);
            t_end.push_back(8.f);
            tau.push_back(-std::log1p(-u(r)));
            t0.push_back(0.f);
        }
        t.resize(kFlights);
        m.resize(kFlights);
        hit.resize(kFlights);
    }
    MarchFlights view() {
        return {ox.data(),    oy.data(),  oz.data(), dx.data(), dy.data(), dz.data(),
                t_end.data(), tau.data(), t.data(),  m.data(),  hit.data()};
    }
};

template <void (*March)(const MajorantGrid&, const MarchFlights&, std::size_t)>
void BM_march(benchmark::State& state) {
    MarchSetup s;
    for (auto _ : state) {
        s.t = s.t0;
        March(s.g, s.view(), kFlights);
        benchmark::DoNotOptimize(s.t.data());
    }
    state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(kFlights));
}

}  // namespace

BENCHMARK(BM_march<march_majorant>)->Name("majorant_march_simd");
BENCHMARK(BM_march<march_majorant_scalar>)->Name("majorant_march_scalar");
