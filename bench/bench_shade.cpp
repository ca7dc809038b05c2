// Google Benchmark: the Lambertian shading kernel (kernels/diffuse_shade.h) against its scalar
// twin on the same 128-lane table the path tracer fills (vertices per second): what the SIMD
// part of the shade stage costs, without the filling and reading back around it.
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>
#include <vector>

#include "engine/core/aligned.h"
#include "kernels/diffuse_shade.h"

using namespace foton::kern;

namespace {

constexpr std::size_t kLanes = 128;

struct Table {
    foton::AlignedVector<float> data = foton::AlignedVector<float>(kDiffuseColumns * kLanes);
    float* col(uint32_t c) { return data.data() + std::size_t(c) * kLanes; }
    Table() {
        std::mt19937 g(5);
        std::uniform_real_distribution<float> u(0.f, 1.f);
        std::normal_distribution<float> n;
        auto unit = [&](uint32_t c, std::size_t i, float lift) {
            float x = n(g), y = n(g), z = std::fabs(n(g)) + lift;
            const float len = std::sqrt(x * x + y * y + z * z);
            col(c)[i] = x / len;
            col(c + 1)[i] = y / len;
            col(c + 2)[i] = z / len;
        };
        for (std::size_t i = 0; i < kLanes; ++i) {
            for (uint32_t c = kDvPx; c <= kDvPz; ++c) col(c)[i] = 500.f * u(g);
            unit(kDvNgx, i, 1.f);
            for (uint32_t c = 0; c < 3; ++c) col(kDvNsx + c)[i] = col(kDvNgx + c)[i];
            col(kDvEps)[i] = 0.01f;
            unit(kDvWox, i, 0.5f);
            for (uint32_t c = kDvRhoR; c <= kDvBetaB; ++c) col(c)[i] = u(g);
            col(kDvEtaScale)[i] = 1.f;
            col(kDvLightPdf)[i] = 0.5f + u(g);
            col(kDvLightFull)[i] = 0.f;
            unit(kDvLwx, i, 0.2f);
            col(kDvLdist)[i] = 300.f;
            for (uint32_t c = 0; c < 3; ++c)
                col(kDvLpx + c)[i] = col(kDvPx + c)[i] + 300.f * col(kDvLwx + c)[i];
            col(kDvLnx)[i] = 0.f;
            col(kDvLny)[i] = -1.f;
            col(kDvLnz)[i] = 0.f;
            for (uint32_t c = kDvLiR; c <= kDvLiB; ++c) col(c)[i] = 15.f;
            // The Cornell box's ceiling light, sampled by the kernel.
            col(kDvLrect)[i] = 1.f;
            col(kDvLightPdf)[i] = 1.f;
            col(kDvLpx)[i] = 212.5f;
            col(kDvLpy)[i] = 554.f;
            col(kDvLpz)[i] = 227.f;
            col(kDvLe1x)[i] = 130.f;
            col(kDvLe2z)[i] = 105.f;
            col(kDvLarea)[i] = 130.f * 105.f;
            col(kDvLu0)[i] = u(g);
            col(kDvLu1)[i] = u(g);
            for (uint32_t c = kDvU0; c <= kDvURoulette; ++c) col(c)[i] = u(g);
        }
    }
};

template <bool kSimd>
void BM_ShadeDiffuse(benchmark::State& state) {
    Table t;
    const DiffuseVertices v{t.data.data(), kLanes};
    const DiffuseRules rules{DiffuseMis::Power, true};
    for (auto _ : state) {
        if (kSimd)
            shade_diffuse(v, kLanes, rules);
        else
            shade_diffuse_scalar(v, kLanes, rules);
        benchmark::ClobberMemory();
    }
    state.counters["vertices/s"] =
        benchmark::Counter(double(kLanes), benchmark::Counter::kIsIterationInvariantRate);
    state.counters["width"] = double(kSimd ? diffuse_shade_width() : 1);
}

}  // namespace

BENCHMARK_TEMPLATE(BM_ShadeDiffuse, true)->Name("shade_diffuse/simd");
BENCHMARK_TEMPLATE(BM_ShadeDiffuse, false)->Name("shade_diffuse/scalar");
