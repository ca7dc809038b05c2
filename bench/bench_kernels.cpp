// Google Benchmark: the SIMD Möller–Trumbore block kernel against its scalar twin, on the
// same rays and triangles (tests per second). The full kernel suite against Embree and
// nanoflann grows here.
#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "kernels/moller_trumbore.h"

using namespace foton::kern;

namespace {
struct Data {
    std::vector<TriangleBlock> blocks;
    std::vector<Ray1> rays;
    Data() {
        std::mt19937 rng(1);
        std::uniform_real_distribution<float> U(-1.f, 1.f);
        blocks.resize(64);
        for (auto& b : blocks) {
            b.clear();
            for (std::size_t l = 0; l < kBlockWidth; ++l) {
                float p0[3] = {U(rng), U(rng), U(rng)}, p1[3], p2[3];
                for (int a = 0; a < 3; ++a) {
                    p1[a] = p0[a] + 0.3f * U(rng);
                    p2[a] = p0[a] + 0.3f * U(rng);
                }
                b.set(l, p0, p1, p2, 0);
            }
        }
        for (int i = 0; i < 1024; ++i)
            rays.push_back({2 * U(rng), 2 * U(rng), 2 * U(rng), U(rng), U(rng), U(rng), 0.f, kInf});
    }
};
const Data& data() {
    static const Data d;
    return d;
}

template <bool kSimd>
void BM_TriangleBlock(benchmark::State& state) {
    const Data& d = data();
    std::size_t hits = 0;
    for (auto _ : state) {
        for (const Ray1& r : d.rays) {
            TriHit h;
            for (const TriangleBlock& b : d.blocks)
                hits += kSimd ? intersect_block(r, b, h) : intersect_block_scalar(r, b, h);
        }
    }
    benchmark::DoNotOptimize(hits);
    const double tests = double(d.rays.size() * d.blocks.size() * kBlockWidth);
    state.counters["tests/s"] =
        benchmark::Counter(tests, benchmark::Counter::kIsIterationInvariantRate);
    state.counters["width"] = double(kBlockWidth);
}
}  // namespace

BENCHMARK_TEMPLATE(BM_TriangleBlock, false)->Name("triangle_block/scalar_twin");
BENCHMARK_TEMPLATE(BM_TriangleBlock, true)->Name("triangle_block/simd");
