// The four pixel sample patterns: structure, and uniformity by a chi-square test.
#include <catch2/catch.hpp>
#include <set>

#include "engine/core/sampler.h"

using namespace foton;

namespace {
// Pearson chi-square of `n_patterns` patterns of `n` points over a k x k histogram.
double chi_square(SamplerKind kind, uint32_t n, int n_patterns, int k) {
    std::vector<double> bins(std::size_t(k * k), 0.0);
    for (int p = 0; p < n_patterns; ++p)
        for (uint32_t i = 0; i < n; ++i) {
            const Point2 s = sample_pattern(kind, i, n, 5, uint64_t(p));
            REQUIRE(s.x >= 0.f);
            REQUIRE(s.x < 1.f);
            REQUIRE(s.y >= 0.f);
            REQUIRE(s.y < 1.f);
            bins[std::size_t(int(s.y * k) * k + int(s.x * k))] += 1.0;
        }
    const double expected = double(n) * n_patterns / double(k * k);
    double chi2 = 0.0;
    for (double b : bins) chi2 += (b - expected) * (b - expected) / expected;
    return chi2;
}
}  // namespace

TEST_CASE("random and jittered patterns are uniform (chi-square)", "[sampler][fast]") {
    // 64 bins: 63 degrees of freedom; the 0.999 quantile is 103.4.
    CHECK(chi_square(SamplerKind::Random, 16, 4000, 8) < 103.4);
    CHECK(chi_square(SamplerKind::Jittered, 16, 4000, 8) < 103.4);
    CHECK(chi_square(SamplerKind::Jittered, 7, 4000, 8) < 103.4);
    // A broken sampler (all points in one half) must fail the same test.
    std::vector<double> bins(64, 0.0);
    for (int i = 0; i < 64000; ++i) bins[std::size_t(i % 32)] += 1.0;
    double chi2 = 0.0;
    for (double b : bins) chi2 += (b - 1000.0) * (b - 1000.0) / 1000.0;
    CHECK(chi2 > 103.4);
}

TEST_CASE("jittered samples stay in their strata", "[sampler][fast]") {
    for (uint32_t n : {1u, 4u, 6u, 16u, 7u}) {
        uint32_t cols, rows;
        stratum_grid(n, cols, rows);
        REQUIRE(cols * rows == n);
        std::set<uint32_t> strata;
        for (uint32_t i = 0; i < n; ++i) {
            const Point2 s = sample_pattern(SamplerKind::Jittered, i, n, 1, 42);
            strata.insert(uint32_t(s.y * rows) * cols + uint32_t(s.x * cols));
        }
        CHECK(strata.size() == n);
    }
}

TEST_CASE("regular and Hammersley patterns are deterministic", "[sampler][fast]") {
    const Point2 c = sample_pattern(SamplerKind::Regular, 0, 1, 0, 0);
    CHECK(c.x == 0.5f);
    CHECK(c.y == 0.5f);
    const Point2 r3 = sample_pattern(SamplerKind::Regular, 3, 4, 9, 17);
    CHECK(r3.x == 0.75f);
    CHECK(r3.y == 0.75f);
    CHECK(radical_inverse2(1) == 0.5f);
    CHECK(radical_inverse2(2) == 0.25f);
    CHECK(radical_inverse2(3) == 0.75f);
    CHECK(radical_inverse2(5) == 0.625f);
    // Centred Hammersley: one point per row and per column of an n x n grid for n = 2^k.
    const uint32_t n = 16;
    std::set<int> xs, ys;
    for (uint32_t i = 0; i < n; ++i) {
        const Point2 h = sample_pattern(SamplerKind::Hammersley, i, n, 123, 456);
        CHECK(h.x == Approx((i + 0.5f) / n));
        xs.insert(int(h.x * n));
        ys.insert(int(h.y * n));
        // Independent of seed and key.
        const Point2 h2 = sample_pattern(SamplerKind::Hammersley, i, n, 1, 2);
        CHECK(h2.x == h.x);
        CHECK(h2.y == h.y);
    }
    CHECK(xs.size() == n);
    CHECK(ys.size() == n);
}
