// Google Benchmark: the photon kd-tree (kernels/point_kdtree.h) against nanoflann's
// KDTreeSingleIndexAdaptor on the same points and queries.
//   points:  N = 100k, 1M, 10M, area-uniform on the dragon's surface (photons on a surface);
//   queries: 16,384 other points on the same surface, unbounded radius;
//   k = 50, 200, 500; single queries, our batched API, and nanoflann's knnSearch.
// nanoflann gets its natural AoS layout and the leaf size that was fastest for it at
// k = 200 (see kNanoflannLeaf). Counters: queries/s (single thread); build time in ms.
#include <benchmark/benchmark.h>
#include <tbb/parallel_invoke.h>
#include <nanoflann.hpp>

#include <algorithm>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "engine/scene/obj_loader.h"
#include "kernels/point_kdtree.h"

using namespace foton;

namespace {

constexpr std::size_t kQueries = 1u << 14;
// Tried 4, 10 (nanoflann's default), 16, 32, 64, 128 at N = 1M, k = 200: 32 was its best.
constexpr std::size_t kNanoflannLeaf = 32;

struct AosCloud {
    std::vector<float> xyz;
    std::size_t kdtree_get_point_count() const { return xyz.size() / 3; }
    float kdtree_get_pt(std::size_t i, std::size_t dim) const { return xyz[3 * i + dim]; }
    template <class Box>
    bool kdtree_get_bbox(Box&) const {
        return false;
    }
};
using NanoTree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, AosCloud>,
                                                     AosCloud, 3, uint32_t>;

struct SoaPoints {
    std::vector<float> x, y, z;
};

// n points area-uniform on the mesh surface.
SoaPoints surface_samples(const TriangleMesh& m, std::size_t n, uint32_t seed) {
    std::vector<double> cdf(m.num_triangles());
    double total = 0.0;
    for (uint32_t t = 0; t < m.num_triangles(); ++t) {
        Vec3 a, b, c;
        m.corners(t, a, b, c);
        total += 0.5 * double(length(cross(b - a, c - a)));
        cdf[t] = total;
    }
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> U(0.0, 1.0);
    SoaPoints p;
    p.x.resize(n), p.y.resize(n), p.z.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        const auto it = std::lower_bound(cdf.begin(), cdf.end(), U(rng) * total);
        const uint32_t t =
            uint32_t(std::min<std::ptrdiff_t>(it - cdf.begin(), long(cdf.size()) - 1));
        Vec3 a, b, c;
        m.corners(t, a, b, c);
        float s = float(U(rng)), r = float(U(rng));
        if (s + r > 1.f) s = 1.f - s, r = 1.f - r;
        const Vec3 q = a + (b - a) * s + (c - a) * r;
        p.x[i] = q.x, p.y[i] = q.y, p.z[i] = q.z;
    }
    return p;
}

const TriangleMesh& dragon() {
    static const TriangleMesh m =
        load_obj(std::string(FOTON_SOURCE_DIR) + "/../shared/meshes/dragon.obj").mesh;
    return m;
}

struct KnnData {
    SoaPoints points, queries;
    AosCloud cloud;
    kern::PointKdTree ours;
    std::unique_ptr<NanoTree> nano;
};

KnnData& data(std::size_t n) {
    static std::map<std::size_t, std::unique_ptr<KnnData>> all;
    auto& slot = all[n];
    if (slot) return *slot;
    // Keep one point set alive at a time: 10M points with both trees is a lot of memory.
    all.clear();
    auto d = std::make_unique<KnnData>();
    d->points = surface_samples(dragon(), n, 17);
    d->queries = surface_samples(dragon(), kQueries, 99);
    d->cloud.xyz.resize(3 * n);
    for (std::size_t i = 0; i < n; ++i) {
        d->cloud.xyz[3 * i] = d->points.x[i];
        d->cloud.xyz[3 * i + 1] = d->points.y[i];
        d->cloud.xyz[3 * i + 2] = d->points.z[i];
    }
    d->ours.build(d->points.x.data(), d->points.y.data(), d->points.z.data(), n);
    d->nano = std::make_unique<NanoTree>(3, d->cloud,
                                         nanoflann::KDTreeSingleIndexAdaptorParams(kNanoflannLeaf));
    d->nano->buildIndex();
    return *(all[n] = std::move(d));
}

void per_query(benchmark::State& state, std::size_t queries, double neighbours) {
    state.counters["queries/s"] =
        benchmark::Counter(double(queries), benchmark::Counter::kIsIterationInvariantRate);
    state.counters["found"] = neighbours / double(queries) / double(state.iterations());
}

void BM_KnnOurs(benchmark::State& state, std::size_t n, uint32_t k) {
    KnnData& d = data(n);
    std::vector<uint32_t> idx(k);
    std::vector<float> d2(k);
    double found = 0;
    for (auto _ : state)
        for (std::size_t i = 0; i < kQueries; ++i) {
            const float q[3] = {d.queries.x[i], d.queries.y[i], d.queries.z[i]};
            found += d.ours.knn(q, kern::kInf, k, idx.data(), d2.data());
            benchmark::DoNotOptimize(d2.data());
        }
    per_query(state, kQueries, found);
}

void BM_KnnOursBatch(benchmark::State& state, std::size_t n, uint32_t k) {
    KnnData& d = data(n);
    const std::vector<float> r2(kQueries, kern::kInf);
    kern::KnnBatchResult res;
    double found = 0;
    for (auto _ : state) {
        d.ours.knn_batch(d.queries.x.data(), d.queries.y.data(), d.queries.z.data(), r2.data(),
                         kQueries, k, res);
        for (uint32_t c : res.count) found += c;
        benchmark::DoNotOptimize(res.dist2.data());
    }
    per_query(state, kQueries, found);
}

void BM_KnnNanoflann(benchmark::State& state, std::size_t n, uint32_t k) {
    KnnData& d = data(n);
    std::vector<uint32_t> idx(k);
    std::vector<float> d2(k);
    double found = 0;
    for (auto _ : state)
        for (std::size_t i = 0; i < kQueries; ++i) {
            const float q[3] = {d.queries.x[i], d.queries.y[i], d.queries.z[i]};
            found += double(d.nano->knnSearch(q, k, idx.data(), d2.data()));
            benchmark::DoNotOptimize(d2.data());
        }
    per_query(state, kQueries, found);
}

void BM_BuildOurs(benchmark::State& state, std::size_t n, bool parallel) {
    KnnData& d = data(n);
    const kern::PointKdTree::ParallelInvoke par = [](const std::function<void()>& a,
                                                     const std::function<void()>& b) {
        tbb::parallel_invoke(a, b);
    };
    for (auto _ : state) {
        kern::PointKdTree t;
        t.build(d.points.x.data(), d.points.y.data(), d.points.z.data(), n,
                parallel ? par : kern::PointKdTree::ParallelInvoke{});
        benchmark::DoNotOptimize(t.order().data());
    }
    state.counters["points/s"] =
        benchmark::Counter(double(n), benchmark::Counter::kIsIterationInvariantRate);
}

void BM_BuildNanoflann(benchmark::State& state, std::size_t n) {
    KnnData& d = data(n);
    for (auto _ : state) {
        NanoTree t(3, d.cloud, nanoflann::KDTreeSingleIndexAdaptorParams(kNanoflannLeaf));
        t.buildIndex();
        benchmark::DoNotOptimize(&t);
    }
    state.counters["points/s"] =
        benchmark::Counter(double(n), benchmark::Counter::kIsIterationInvariantRate);
}

const bool registered = [] {
    const std::pair<std::size_t, const char*> sizes[] = {
        {100000, "100k"}, {1000000, "1M"}, {10000000, "10M"}};
    for (const auto& [n, tag] : sizes) {
        const std::string t = tag;
        benchmark::RegisterBenchmark(("kdtree_build/ours/" + t).c_str(), BM_BuildOurs, n, false)
            ->Unit(benchmark::kMillisecond);
        benchmark::RegisterBenchmark(("kdtree_build/ours_parallel/" + t).c_str(), BM_BuildOurs, n,
                                     true)
            ->Unit(benchmark::kMillisecond);
        benchmark::RegisterBenchmark(("kdtree_build/nanoflann/" + t).c_str(), BM_BuildNanoflann, n)
            ->Unit(benchmark::kMillisecond);
        for (uint32_t k : {50u, 200u, 500u}) {
            const std::string tk = t + "/k" + std::to_string(k);
            benchmark::RegisterBenchmark(("knn/ours/" + tk).c_str(), BM_KnnOurs, n, k)
                ->Unit(benchmark::kMillisecond);
            benchmark::RegisterBenchmark(("knn/ours_batch/" + tk).c_str(), BM_KnnOursBatch, n, k)
                ->Unit(benchmark::kMillisecond);
            benchmark::RegisterBenchmark(("knn/nanoflann/" + tk).c_str(), BM_KnnNanoflann, n, k)
                ->Unit(benchmark::kMillisecond);
        }
    }
    return true;
}();

}  // namespace
