// Google Benchmark: the shading kernels against their scalar twins on the same 128-lane table
// (vertices per second): Lambertian and glossy (kernels/diffuse_shade.h), the light tracer's
// (kernels/importance_shade.h) and specular (kernels/specular_shade.h) vertices, and the
// random-number tables the path tracer draws for them (counter-based, Sobol', Z-Sobol'; numbers per
// second), and the light BVH's descent (kernels/light_tree.h; picks per second, on a plaza of 4,096
// lamps as bench/many_lights renders). What the SIMD parts of the shade stage cost, without the
// filling and reading back around them.
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>
#include <vector>

#include "engine/core/aligned.h"
#include "engine/scene/light_bvh.h"
#include "kernels/counter_hash.h"
#include "kernels/diffuse_shade.h"
#include "kernels/halton_net.h"
#include "kernels/importance_shade.h"
#include "kernels/light_tree.h"
#include "kernels/sobol_net.h"
#include "kernels/specular_shade.h"
#include "kernels/zsobol_net.h"

using namespace foton::kern;

namespace {

constexpr std::size_t kLanes = 128;

struct Table {
    foton::AlignedVector<float> data = foton::AlignedVector<float>(kShadeColumns * kLanes);
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
            col(kDvLkind)[i] = 1.f;
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

// The diffuse kernel (or its twin) over the table's lanes, timed: vertices per second.
template <bool kSimd>
void run_shade_diffuse(benchmark::State& state, Table& t) {
    const ShadeTable v{t.data.data(), kLanes};
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
    state.counters["width"] = double(kSimd ? shade_width() : 1);
}

template <bool kSimd>
void BM_ShadeDiffuse(benchmark::State& state) {
    Table t;
    run_shade_diffuse<kSimd>(state, t);
}

// Glossy vertices on the diffuse table (kernels/glossy_lanes.h), a quarter each: Lambert +
// modified Phong (exponent 40, the thesis' Phong), Lambert + Beckmann plastic (Cook-Torrance,
// dielectric Fresnel), rough gold (Beckmann alone, conductor Fresnel), brushed aluminium
// (Ashikhmin-Shirley 20 x 800, conductor Fresnel).
template <bool kSimd>
void BM_ShadeGlossy(benchmark::State& state) {
    Table t;
    std::mt19937 g(9);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    for (std::size_t i = 0; i < kLanes; ++i) {
        const std::size_t kind = (i / 32) % 4;
        t.col(kDvGlossKind)[i] = kind == 0   ? kGlossPhong
                                 : kind == 3 ? kGlossCosPower
                                             : kGlossBeckmann;
        for (uint32_t c = kDvGlossR; c <= kDvGlossB; ++c) t.col(c)[i] = 0.8f;
        t.col(kDvGlossNu)[i] = kind == 0 ? 40.f : kind == 3 ? 20.f : 0.15f;
        t.col(kDvGlossNv)[i] = kind == 0 ? 40.f : kind == 3 ? 800.f : 0.15f;
        t.col(kDvDiffuseWeight)[i] = kind < 2 ? 0.5f : 0.f;
        if (kind >= 2)
            for (uint32_t c = kDvRhoR; c <= kDvRhoB; ++c) t.col(c)[i] = 0.f;
        t.col(kDvGlossWeight)[i] = 0.8f;
        t.col(kDvGlossFirst)[i] = kind < 2 ? 0.f : 1.f;
        t.col(kDvFresnel)[i] = kind == 1 ? 2.f : kind >= 2 ? 1.f : 0.f;
        t.col(kDvIor)[i] = 1.5f;
        t.col(kDvEtaR)[i] = 0.2f;
        t.col(kDvEtaG)[i] = 0.4f;
        t.col(kDvEtaB)[i] = 1.4f;
        for (uint32_t c = kDvKR; c <= kDvKB; ++c) t.col(c)[i] = 3.f;
        t.col(kDvUChoice)[i] = u(g);
    }
    run_shade_diffuse<kSimd>(state, t);
}

// The light tracer's vertices (kernels/importance_shade.h) on the diffuse table's Lambertian
// surfaces, the eye at the ceiling light's corner: the connection and the continuation.
template <bool kSimd>
void BM_ShadeImportance(benchmark::State& state) {
    Table t;
    const ShadeTable v{t.data.data(), kLanes};
    for (auto _ : state) {
        if (kSimd)
            shade_importance(v, kLanes, true);
        else
            shade_importance_scalar(v, kLanes, true);
        benchmark::ClobberMemory();
    }
    state.counters["vertices/s"] =
        benchmark::Counter(double(kLanes), benchmark::Counter::kIsIterationInvariantRate);
    state.counters["width"] = double(kSimd ? shade_width() : 1);
}

// Mirrors and dielectrics alternating, on the diffuse table's surfaces.
template <bool kSimd>
void BM_ShadeSpecular(benchmark::State& state) {
    Table t;
    std::mt19937 g(8);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    for (std::size_t i = 0; i < kLanes; ++i) {
        t.col(kDvSpecKind)[i] = i % 2 ? 2.f : 1.f;
        for (uint32_t c = kDvSpecR; c <= kDvTransB; ++c) t.col(c)[i] = 0.9f;
        t.col(kDvIor)[i] = 1.5f;
        t.col(kDvLobeWeight)[i] = 0.9f;
        t.col(kDvUChoice)[i] = u(g);
        t.col(kDvFront)[i] = 1.f;
    }
    const ShadeTable v{t.data.data(), kLanes};
    for (auto _ : state) {
        if (kSimd)
            shade_specular(v, kLanes, true);
        else
            shade_specular_scalar(v, kLanes, true);
        benchmark::ClobberMemory();
    }
    state.counters["vertices/s"] =
        benchmark::Counter(double(kLanes), benchmark::Counter::kIsIterationInvariantRate);
}

// A bounce's eight numbers for 128 paths: counter-based (0), Sobol' (1), Z-Sobol' (2; the
// paths of one render pass, which share the pass's key), Halton (3; dimensions 10-17, bases
// 31 to 61).
template <int kKind, bool kSimd>
void BM_NumberTable(benchmark::State& state) {
    std::mt19937_64 g(3);
    std::vector<uint64_t> keys(kLanes), zindex(kLanes);
    std::vector<uint32_t> index(kLanes), count(kLanes, 16), bits(kLanes, 22);
    for (std::size_t i = 0; i < kLanes; ++i) {
        keys[i] = kKind == 2 ? 0x5eed5eedull : g();
        index[i] = uint32_t(i % 16);
        zindex[i] = g() & ((1ull << 22) - 1);
    }
    const uint64_t dims[8] = {9, 10, 13, 14, 8, 11, 12, 15};
    const uint32_t pairs[4] = {5, 6, 7, 8};
    std::vector<float> out(8 * kLanes);
    for (auto _ : state) {
        if (kKind == 0) {
            if (kSimd)
                uniform_table(0x1234, keys.data(), kLanes, dims, 8, out.data(), kLanes);
            else
                uniform_table_scalar(0x1234, keys.data(), kLanes, dims, 8, out.data(), kLanes);
        } else if (kKind == 1) {
            if (kSimd)
                sobol::sample_table(1, index.data(), count.data(), keys.data(), kLanes, pairs, 4,
                                    out.data(), kLanes);
            else
                sobol::sample_table_scalar(1, index.data(), count.data(), keys.data(), kLanes,
                                           pairs, 4, out.data(), kLanes);
        } else if (kKind == 3) {
            const uint32_t hdims[8] = {10, 11, 12, 13, 14, 15, 16, 17};
            if (kSimd)
                halton::sample_table(1, index.data(), keys.data(), kLanes, hdims, 8, out.data(),
                                     kLanes);
            else
                halton::sample_table_scalar(1, index.data(), keys.data(), kLanes, hdims, 8,
                                            out.data(), kLanes);
        } else {
            if (kSimd)
                zsobol::sample_table(zindex.data(), bits.data(), keys.data(), kLanes, pairs, 4,
                                     out.data(), kLanes);
            else
                zsobol::sample_table_scalar(zindex.data(), bits.data(), keys.data(), kLanes, pairs,
                                            4, out.data(), kLanes);
        }
        benchmark::ClobberMemory();
    }
    state.counters["numbers/s"] =
        benchmark::Counter(double(8 * kLanes), benchmark::Counter::kIsIterationInvariantRate);
}

}  // namespace

// 4,096 downward lamps (small triangles) 2.5-4 units over a 40 x 40 floor, and 1,024 floor
// points looking up: the many-lights plaza's tree and queries.
template <bool kSimd>
void BM_LightPick(benchmark::State& state) {
    std::mt19937 g(3);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    std::vector<foton::LightBounds> bounds;
    for (int k = 0; k < 4096; ++k) {
        foton::LightBounds b;
        const foton::Vec3 c{40.f * u(g) - 20.f, 2.5f + 1.5f * u(g), 40.f * u(g) - 20.f};
        b.box.extend(c - foton::Vec3{0.15f, 0.f, 0.15f});
        b.box.extend(c + foton::Vec3{0.15f, 0.f, 0.15f});
        b.axis = {0.f, -1.f, 0.f};
        b.phi = 0.1f + 3.f * u(g);
        bounds.push_back(b);
    }
    foton::LightBvh bvh;
    bvh.build(bounds);
    constexpr std::size_t n = 1024;
    std::vector<float> px(n), py(n, 0.f), pz(n), nx(n, 0.f), ny(n, 1.f), nz(n, 0.f), uu(n), pmf(n);
    std::vector<uint32_t> light(n);
    for (std::size_t i = 0; i < n; ++i) {
        px[i] = 40.f * u(g) - 20.f;
        pz[i] = 40.f * u(g) - 20.f;
        uu[i] = u(g);
    }
    const LightQueries q{px.data(), py.data(), pz.data(),    nx.data(), ny.data(),
                         nz.data(), uu.data(), light.data(), pmf.data()};
    for (auto _ : state) {
        if (kSimd)
            pick_lights(bvh.tree(), q, n);
        else
            pick_lights_scalar(bvh.tree(), q, n);
        benchmark::ClobberMemory();
    }
    state.counters["picks/s"] =
        benchmark::Counter(double(n), benchmark::Counter::kIsIterationInvariantRate);
}

BENCHMARK_TEMPLATE(BM_ShadeDiffuse, true)->Name("shade_diffuse/simd");
BENCHMARK_TEMPLATE(BM_ShadeDiffuse, false)->Name("shade_diffuse/scalar");
BENCHMARK_TEMPLATE(BM_ShadeGlossy, true)->Name("shade_glossy/simd");
BENCHMARK_TEMPLATE(BM_ShadeGlossy, false)->Name("shade_glossy/scalar");
BENCHMARK_TEMPLATE(BM_ShadeImportance, true)->Name("shade_importance/simd");
BENCHMARK_TEMPLATE(BM_ShadeImportance, false)->Name("shade_importance/scalar");
BENCHMARK_TEMPLATE(BM_ShadeSpecular, true)->Name("shade_specular/simd");
BENCHMARK_TEMPLATE(BM_ShadeSpecular, false)->Name("shade_specular/scalar");
BENCHMARK_TEMPLATE(BM_NumberTable, 0, true)->Name("numbers_uniform/simd");
BENCHMARK_TEMPLATE(BM_NumberTable, 0, false)->Name("numbers_uniform/scalar");
BENCHMARK_TEMPLATE(BM_NumberTable, 1, true)->Name("numbers_sobol/simd");
BENCHMARK_TEMPLATE(BM_NumberTable, 1, false)->Name("numbers_sobol/scalar");
BENCHMARK_TEMPLATE(BM_NumberTable, 2, true)->Name("numbers_zsobol/simd");
BENCHMARK_TEMPLATE(BM_NumberTable, 2, false)->Name("numbers_zsobol/scalar");
BENCHMARK_TEMPLATE(BM_NumberTable, 3, true)->Name("numbers_halton/simd");
BENCHMARK_TEMPLATE(BM_NumberTable, 3, false)->Name("numbers_halton/scalar");
BENCHMARK_TEMPLATE(BM_LightPick, true)->Name("light_pick/simd");
BENCHMARK_TEMPLATE(BM_LightPick, false)->Name("light_pick/scalar");
