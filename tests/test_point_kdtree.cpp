// The photon kd-tree returns exactly the brute-force k nearest (ties aside) and range sets;
// the SIMD leaf test agrees with its scalar twin; batched queries equal single ones.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <future>
#include <numeric>
#include <random>

#include "kernels/point_kdtree.h"

using namespace foton::kern;

namespace {

struct Cloud {
    std::vector<float> x, y, z;
    std::size_t size() const { return x.size(); }
    void add(float a, float b, float c) {
        x.push_back(a);
        y.push_back(b);
        z.push_back(c);
    }
};

Cloud uniform_cloud(std::size_t n, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> U(-1.f, 1.f);
    Cloud c;
    for (std::size_t i = 0; i < n; ++i) c.add(U(rng), U(rng), U(rng));
    return c;
}

// Tight Gaussian clusters, a flat sheet (photons on a wall) and exact duplicates: the
// distributions a photon map actually holds.
Cloud clustered_cloud(std::size_t n, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> U(-1.f, 1.f);
    std::normal_distribution<float> N(0.f, 0.01f);
    Cloud c;
    float cx[8], cy[8], cz[8];
    for (int i = 0; i < 8; ++i) cx[i] = U(rng), cy[i] = U(rng), cz[i] = U(rng);
    for (std::size_t i = 0; i < n; ++i) {
        switch (i % 4) {
            case 0:
            case 1: {
                const int k = int(rng() % 8);
                c.add(cx[k] + N(rng), cy[k] + N(rng), cz[k] + N(rng));
                break;
            }
            case 2:
                c.add(U(rng), 0.25f, U(rng));
                break;
            default:
                c.add(cx[0], cy[0], cz[0]);  // the same point many times
        }
    }
    return c;
}

struct Neighbour {
    float d2;
    uint32_t index;
};

std::vector<Neighbour> brute_knn(const Cloud& c, const float q[3], float max_d2, uint32_t k) {
    std::vector<Neighbour> all;
    for (std::size_t i = 0; i < c.size(); ++i) {
        const float dx = c.x[i] - q[0], dy = c.y[i] - q[1], dz = c.z[i] - q[2];
        const float d2 = dx * dx + dy * dy + dz * dz;
        if (d2 < max_d2) all.push_back({d2, uint32_t(i)});
    }
    std::sort(all.begin(), all.end(),
              [](const Neighbour& a, const Neighbour& b) { return a.d2 < b.d2; });
    if (all.size() > k) all.resize(k);
    return all;
}

// Same multiset of distances; same indices for every distance below the largest (the
// largest may be tied with points left out).
void check_knn(const Cloud& c, const PointKdTree& tree, const float q[3], float max_d2,
               uint32_t k) {
    const auto want = brute_knn(c, q, max_d2, k);
    std::vector<uint32_t> idx(std::max(k, 1u));
    std::vector<float> d2(std::max(k, 1u));
    const uint32_t n = tree.knn(q, max_d2, k, idx.data(), d2.data());
    REQUIRE(n == want.size());
    if (n == 0) return;
    // Heap order: the farthest first.
    CHECK(d2[0] == want.back().d2);
    sort_knn_result(n, idx.data(), d2.data());
    for (uint32_t i = 0; i < n; ++i) REQUIRE(d2[i] == want[i].d2);
    std::vector<uint32_t> got_close, want_close;
    for (uint32_t i = 0; i < n; ++i) {
        if (d2[i] < want.back().d2) got_close.push_back(idx[i]);
        if (want[i].d2 < want.back().d2) want_close.push_back(want[i].index);
    }
    std::sort(got_close.begin(), got_close.end());
    std::sort(want_close.begin(), want_close.end());
    REQUIRE(got_close == want_close);
}

PointKdTree build(const Cloud& c) {
    PointKdTree t;
    t.build(c.x.data(), c.y.data(), c.z.data(), c.size());
    return t;
}

}  // namespace

TEST_CASE("kd-tree kNN equals brute force on random and clustered points", "[kernel][kdtree]") {
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> U(-1.2f, 1.2f);
    for (std::size_t n : {1u, 5u, 16u, 17u, 100u, 1000u, 20000u}) {
        for (int kind = 0; kind < 2; ++kind) {
            const Cloud c = kind == 0 ? uniform_cloud(n, uint32_t(n)) : clustered_cloud(n, 9);
            const PointKdTree tree = build(c);
            REQUIRE(tree.size() == n);
            for (int i = 0; i < 60; ++i) {
                // Queries anywhere, and exactly on stored points.
                float q[3] = {U(rng), U(rng), U(rng)};
                if (i % 3 == 0) {
                    const std::size_t j = rng() % n;
                    q[0] = c.x[j], q[1] = c.y[j], q[2] = c.z[j];
                }
                for (uint32_t k : {1u, 8u, 50u, 200u, uint32_t(n) + 7u}) {
                    check_knn(c, tree, q, kInf, k);
                    check_knn(c, tree, q, 0.05f, k);
                }
            }
        }
    }
}

TEST_CASE("kd-tree handles empty maps and k = 0", "[kernel][kdtree]") {
    PointKdTree tree;
    tree.build(nullptr, nullptr, nullptr, 0);
    const float q[3] = {0, 0, 0};
    uint32_t idx[4];
    float d2[4];
    CHECK(tree.knn(q, kInf, 4, idx, d2) == 0);
    std::vector<uint32_t> ri;
    std::vector<float> rd;
    CHECK(tree.radius(q, 1.f, ri, rd) == 0);
    const Cloud c = uniform_cloud(50, 1);
    const PointKdTree t2 = build(c);
    CHECK(t2.knn(q, kInf, 0, idx, d2) == 0);
}

TEST_CASE("kd-tree SIMD leaf test agrees with the scalar twin", "[kernel][kdtree]") {
    const Cloud c = clustered_cloud(30000, 4);
    const PointKdTree tree = build(c);
    std::mt19937 rng(8);
    std::uniform_real_distribution<float> U(-1.f, 1.f);
    const uint32_t k = 100;
    std::vector<uint32_t> i1(k), i2(k);
    std::vector<float> d1(k), d2(k);
    for (int i = 0; i < 2000; ++i) {
        const float q[3] = {U(rng), U(rng), U(rng)};
        const float r2 = i % 2 ? kInf : 0.01f;
        const uint32_t n1 = tree.knn(q, r2, k, i1.data(), d1.data());
        const uint32_t n2 = tree.knn_scalar(q, r2, k, i2.data(), d2.data());
        REQUIRE(n1 == n2);
        for (uint32_t j = 0; j < n1; ++j) {
            REQUIRE(i1[j] == i2[j]);
            REQUIRE(d1[j] == d2[j]);
        }
    }
}

TEST_CASE("kd-tree batched kNN equals single queries", "[kernel][kdtree]") {
    const Cloud c = uniform_cloud(10000, 5);
    const PointKdTree tree = build(c);
    const Cloud qs = uniform_cloud(257, 6);
    std::vector<float> r2(qs.size());
    for (std::size_t i = 0; i < r2.size(); ++i) r2[i] = i % 3 ? kInf : 0.02f;
    const uint32_t k = 50;
    KnnBatchResult res;
    tree.knn_batch(qs.x.data(), qs.y.data(), qs.z.data(), r2.data(), qs.size(), k, res);
    REQUIRE(res.count.size() == qs.size());
    std::vector<uint32_t> idx(k);
    std::vector<float> d2(k);
    for (std::size_t i = 0; i < qs.size(); ++i) {
        const float q[3] = {qs.x[i], qs.y[i], qs.z[i]};
        const uint32_t n = tree.knn(q, r2[i], k, idx.data(), d2.data());
        REQUIRE(res.count[i] == n);
        for (uint32_t j = 0; j < n; ++j) {
            REQUIRE(res.index[i * k + j] == idx[j]);
            REQUIRE(res.dist2[i * k + j] == d2[j]);
        }
    }
}

TEST_CASE("kd-tree range query equals brute force", "[kernel][kdtree]") {
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> U(-1.f, 1.f);
    for (int kind = 0; kind < 2; ++kind) {
        const Cloud c = kind ? clustered_cloud(20000, 2) : uniform_cloud(20000, 2);
        const PointKdTree tree = build(c);
        std::vector<uint32_t> idx;
        std::vector<float> d2;
        for (int i = 0; i < 300; ++i) {
            const float q[3] = {U(rng), U(rng), U(rng)};
            const float r2 = (i % 4 == 0) ? 0.f : 0.002f * float(i % 7 + 1);
            tree.radius(q, r2, idx, d2);
            std::vector<uint32_t> want;
            for (std::size_t j = 0; j < c.size(); ++j) {
                const float dx = c.x[j] - q[0], dy = c.y[j] - q[1], dz = c.z[j] - q[2];
                const float d = dx * dx + dy * dy + dz * dz;
                if (d < r2) want.push_back(uint32_t(j));
            }
            for (std::size_t j = 0; j < idx.size(); ++j) {
                const uint32_t p = idx[j];
                const float dx = c.x[p] - q[0], dy = c.y[p] - q[1], dz = c.z[p] - q[2];
                REQUIRE(d2[j] == dx * dx + dy * dy + dz * dz);
            }
            std::sort(idx.begin(), idx.end());
            REQUIRE(idx == want);
        }
    }
}

TEST_CASE("kd-tree parallel build equals the serial build", "[kernel][kdtree]") {
    const Cloud c = clustered_cloud(200000, 12);
    PointKdTree serial, parallel;
    serial.build(c.x.data(), c.y.data(), c.z.data(), c.size());
    parallel.build(c.x.data(), c.y.data(), c.z.data(), c.size(),
                   [](const std::function<void()>& a, const std::function<void()>& b) {
                       auto f = std::async(std::launch::async, a);
                       b();
                       f.get();
                   });
    REQUIRE(serial.order() == parallel.order());
    // Every bucket is full except the last one: the padding is shorter than one bucket.
    const auto& order = serial.order();
    const std::size_t pad = std::count(order.begin(), order.end(), kInvalidId);
    CHECK(pad < kKdBucket);
    CHECK(order.size() - pad == c.size());
    std::vector<uint32_t> sorted(order.begin(), order.end() - long(pad));
    std::sort(sorted.begin(), sorted.end());
    for (std::size_t i = 0; i < sorted.size(); ++i) REQUIRE(sorted[i] == i);
}
