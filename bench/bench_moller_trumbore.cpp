// Google Benchmark: the SIMD Möller–Trumbore block kernel against its scalar twin, on the
// same rays and triangles (tests per second), in both shapes: one ray against a block of W
// triangles, and a packet of W rays against one triangle.
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

// The packet shape: W rays (SoA) against one triangle at a time, every triangle of the data.
template <bool kSimd>
void BM_TrianglePacket(benchmark::State& state) {
    const Data& d = data();
    std::vector<RayPacket> packets(d.rays.size() / kBlockWidth);
    for (std::size_t i = 0; i < packets.size() * kBlockWidth; ++i) {
        RayPacket& p = packets[i / kBlockWidth];
        const std::size_t l = i % kBlockWidth;
        const Ray1& r = d.rays[i];
        p.ox[l] = r.ox, p.oy[l] = r.oy, p.oz[l] = r.oz;
        p.dx[l] = r.dx, p.dy[l] = r.dy, p.dz[l] = r.dz, p.tmin[l] = r.tmin;
    }
    std::size_t hits = 0;
    for (auto _ : state) {
        for (const RayPacket& p : packets) {
            PacketHits h;
            for (std::size_t l = 0; l < kBlockWidth; ++l) h.t[l] = kInf, h.id[l] = kInvalidId;
            for (const TriangleBlock& b : d.blocks)
                for (std::size_t tri = 0; tri < kBlockWidth; ++tri) {
                    if (kSimd) {
                        hits += intersect_packet(p, b, tri, h) != 0;
                        continue;
                    }
                    for (std::size_t l = 0; l < kBlockWidth; ++l) {
                        const Ray1 r{p.ox[l], p.oy[l], p.oz[l],   p.dx[l],
                                     p.dy[l], p.dz[l], p.tmin[l], h.t[l]};
                        float t, u, v;
                        if (intersect_triangle_scalar(
                                r, b.v0x[tri], b.v0y[tri], b.v0z[tri], b.e1x[tri], b.e1y[tri],
                                b.e1z[tri], b.e2x[tri], b.e2y[tri], b.e2z[tri], h.t[l], t, u, v)) {
                            h.t[l] = t, h.u[l] = u, h.v[l] = v, h.id[l] = b.id[tri];
                            ++hits;
                        }
                    }
                }
        }
    }
    benchmark::DoNotOptimize(hits);
    const double tests = double(packets.size() * kBlockWidth * d.blocks.size() * kBlockWidth);
    state.counters["tests/s"] =
        benchmark::Counter(tests, benchmark::Counter::kIsIterationInvariantRate);
    state.counters["width"] = double(kBlockWidth);
}
}  // namespace

BENCHMARK_TEMPLATE(BM_TrianglePacket, false)->Name("triangle_packet/scalar_twin");
BENCHMARK_TEMPLATE(BM_TrianglePacket, true)->Name("triangle_packet/simd");
BENCHMARK_TEMPLATE(BM_TriangleBlock, false)->Name("triangle_block/scalar_twin");
BENCHMARK_TEMPLATE(BM_TriangleBlock, true)->Name("triangle_block/simd");
