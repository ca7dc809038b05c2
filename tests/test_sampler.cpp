// The four pixel sample patterns: structure, and uniformity by a chi-square test.
#include <algorithm>
#include <bit>
#include <catch2/catch.hpp>
#include <cmath>
#include <iterator>
#include <random>
#include <set>
#include <vector>

#include "engine/core/halton.h"
#include "engine/core/rng.h"
#include "engine/core/rng_streams.h"
#include "engine/core/sampler.h"
#include "engine/core/sobol.h"
#include "engine/core/zsobol.h"
#include "kernels/counter_hash.h"
#include "kernels/sobol_net.h"
#include "kernels/zsobol_net.h"

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

TEST_CASE("scrambled Sobol': every pair of every pixel is a (0, m, 2)-net", "[sampler][fast]") {
    // 2^m points of a pair: each elementary interval of area 2^-m (2^a by 2^(m-a) cells)
    // holds exactly one, whatever the scramble, permutation, key or pair.
    for (uint32_t m : {2u, 4u, 6u, 8u}) {
        const uint32_t n = 1u << m;
        for (uint64_t key : {1ull, 77ull, 123456789ull})
            for (uint32_t pair : {0u, 1u, 5u, 30u}) {
                std::vector<Point2> pts;
                for (uint32_t i = 0; i < n; ++i) {
                    Point2 p;
                    sobol::sample2(i, n, 3, key, pair, p.x, p.y);
                    pts.push_back(p);
                }
                for (uint32_t a = 0; a <= m; ++a) {
                    const uint32_t cx = 1u << a, cy = 1u << (m - a);
                    std::vector<int> count(n, 0);
                    for (const Point2& p : pts) {
                        REQUIRE(p.x >= 0.f);
                        REQUIRE(p.x < 1.f);
                        REQUIRE(p.y >= 0.f);
                        REQUIRE(p.y < 1.f);
                        ++count[uint32_t(p.y * float(cy)) * cx + uint32_t(p.x * float(cx))];
                    }
                    for (int c : count) REQUIRE(c == 1);
                }
                // sample1 gives the same coordinates.
                CHECK(sobol::sample1(3 % n, n, 3, key, pair, 1) == pts[3 % n].y);
            }
    }
}

TEST_CASE("scrambled Sobol': permutations are bijections, pairs are uncorrelated",
          "[sampler][fast]") {
    for (uint32_t n : {1u, 2u, 3u, 7u, 64u, 100u, 1000u}) {
        std::set<uint32_t> seen;
        for (uint32_t i = 0; i < n; ++i) {
            const uint32_t p = sobol::permute(i, n, 42 + n);
            REQUIRE(p < n);
            seen.insert(p);
        }
        CHECK(seen.size() == n);
    }
    // Over many pixels, pair 1's x and pair 2's x of the same sample are uncorrelated, and
    // each is uniform on average.
    const int pixels = 4000;
    const uint32_t n = 16;
    double sx = 0, sy = 0, sxy = 0, sxx = 0, syy = 0;
    for (int k = 0; k < pixels; ++k)
        for (uint32_t i = 0; i < n; ++i) {
            const double x = sobol::sample1(i, n, 9, uint64_t(k), 1, 0);
            const double y = sobol::sample1(i, n, 9, uint64_t(k), 2, 0);
            sx += x, sy += y, sxy += x * y, sxx += x * x, syy += y * y;
        }
    const double N = double(pixels) * n;
    const double cov = sxy / N - (sx / N) * (sy / N);
    const double corr =
        cov / std::sqrt((sxx / N - (sx / N) * (sx / N)) * (syy / N - (sy / N) * (sy / N)));
    INFO("correlation " << corr << ", means " << sx / N << " " << sy / N);
    CHECK(std::fabs(corr) < 0.02);
    CHECK(sx / N == Approx(0.5).epsilon(0.01));
}

TEST_CASE("randomised Halton: radical inverses, stratified in every base, scrambles decorrelate",
          "[sampler][fast]") {
    // The plain radical inverse: 1 -> 1/b, b + 1 -> 1/b + 1/b^2.
    CHECK(halton::radical_inverse(1, 3) == Approx(1.0 / 3));
    CHECK(halton::radical_inverse(4, 3) == Approx(1.0 / 3 + 1.0 / 9));
    CHECK(halton::radical_inverse(6, 5) == Approx(1.0 / 5 + 1.0 / 25));
    CHECK(halton::prime(0) == 2);
    CHECK(halton::prime(5) == 13);
    CHECK(halton::prime(halton::kDims - 1) == 719);
    // Scrambling keeps the stratification of each base: the first b^2 points of dimension k
    // put exactly one point in each of b^2 intervals, for every pixel key.
    // (Up to base 31: with b^2 in the thousands, the odd point lies within a float's rounding
    // of an interval's edge and is counted next door.)
    for (uint32_t dim : {0u, 1u, 2u, 3u, 7u, 10u}) {
        const uint32_t b = halton::prime(dim), n = b * b;
        for (uint64_t key : {1ull, 77ull, 12345ull}) {
            std::vector<int> count(n, 0);
            for (uint32_t i = 0; i < n; ++i) {
                const float x = halton::sample(i, 3, key, dim);
                REQUIRE(x >= 0.f);
                REQUIRE(x < 1.f);
                ++count[std::min<std::size_t>(n - 1, std::size_t(double(x) * n))];
            }
            INFO("dimension " << dim << " (base " << b << "), key " << key);
            CHECK(*std::min_element(count.begin(), count.end()) == 1);
        }
    }
    // The pixel pair (bases 2 and 3): 72 = 2^3 x 3^2 points fill the 8 x 9 grid one each.
    std::vector<int> grid(72, 0);
    for (uint32_t i = 0; i < 72; ++i) {
        const Point2 p = sample_pattern(SamplerKind::Halton, i, 72, 5, 99);
        ++grid[std::size_t(std::min(7, int(p.x * 8)) * 9 + std::min(8, int(p.y * 9)))];
    }
    CHECK(*std::min_element(grid.begin(), grid.end()) == 1);
    // Plain Halton's large bases are strongly correlated over the first points (bases 29 and
    // 31 run in lockstep for i < 29); scrambled per pixel they are not, and every dimension
    // is uniform on average.
    double sx = 0, sy = 0, sxy = 0, sxx = 0, syy = 0;
    const int pixels = 4000;
    const uint32_t n = 16;
    for (int k = 0; k < pixels; ++k)
        for (uint32_t i = 0; i < n; ++i) {
            const double x = halton::sample(i, 9, uint64_t(k), 9);
            const double y = halton::sample(i, 9, uint64_t(k), 10);
            sx += x, sy += y, sxy += x * y, sxx += x * x, syy += y * y;
        }
    const double N = double(pixels) * n;
    const double corr =
        (sxy / N - (sx / N) * (sy / N)) /
        std::sqrt((sxx / N - (sx / N) * (sx / N)) * (syy / N - (sy / N) * (sy / N)));
    INFO("correlation " << corr << ", means " << sx / N << " " << sy / N);
    CHECK(std::fabs(corr) < 0.02);
    CHECK(sx / N == Approx(0.5).epsilon(0.01));
    CHECK(sy / N == Approx(0.5).epsilon(0.01));
    double plain = 0;
    for (uint32_t i = 1; i < 29; ++i)
        plain += double(halton::radical_inverse(i, 29)) * double(halton::radical_inverse(i, 31));
    CHECK(plain / 28 > 0.3);  // E[xy] = 0.25 for independent uniforms; lockstep gives ~1/3
}

namespace {
// Every elementary interval of area 1 / pts.size() (a power of two) holds exactly one point.
bool is_02_net(const std::vector<Point2>& pts) {
    const uint32_t n = uint32_t(pts.size());
    const uint32_t m = uint32_t(std::countr_zero(n));
    for (uint32_t a = 0; a <= m; ++a) {
        const uint32_t cx = 1u << a, cy = 1u << (m - a);
        std::vector<int> count(n, 0);
        for (const Point2& p : pts) {
            if (!(p.x >= 0.f && p.x < 1.f && p.y >= 0.f && p.y < 1.f)) return false;
            ++count[uint32_t(p.y * float(cy)) * cx + uint32_t(p.x * float(cx))];
        }
        for (int c : count)
            if (c != 1) return false;
    }
    return true;
}

Point2 zsample(uint32_t x, uint32_t y, uint32_t res, uint32_t i, uint32_t n, uint64_t seed,
               uint32_t pair) {
    Point2 p;
    zsobol::sample2(zsobol::index_of(x, y, res, res, i, n, seed, 0), pair, p.x, p.y);
    return p;
}
}  // namespace

TEST_CASE("zsobol: Morton order, and its digit permutations map aligned blocks to blocks",
          "[sampler][fast]") {
    // Sobol's second dimension by byte tables equals its definition, a column per index bit.
    for (uint32_t i : {0u, 1u, 2u, 3u, 255u, 256u, 0x12345u, 0xdeadbeefu, 0xffffffffu}) {
        uint32_t v = 1u << 31, want = 0;
        for (uint32_t b = i; b; b >>= 1, v ^= v >> 1)
            if (b & 1u) want ^= v;
        CHECK(sobol::dim1(i) == want);
    }
    CHECK(zsobol::morton2(0, 0) == 0);
    CHECK(zsobol::morton2(1, 0) == 1);
    CHECK(zsobol::morton2(0, 1) == 2);
    CHECK(zsobol::morton2(3, 5) == 0b100111);
    CHECK(zsobol::morton2(0xffffffffu, 0) == 0x5555555555555555ull);
    // Bijective on [0, 2^bits) for even and odd bit counts, and every aligned block of 4^k
    // indices (2^k for the lone bit) lands on an aligned block of the same size.
    for (uint32_t bits : {1u, 4u, 5u, 8u, 9u}) {
        for (uint32_t pair : {0u, 3u, 17u}) {
            std::vector<uint64_t> image(std::size_t(1) << bits);
            std::set<uint64_t> seen;
            for (uint64_t v = 0; v < image.size(); ++v) {
                zsobol::Index s;
                s.index = v;
                s.bits = bits;
                s.key = 99;
                image[v] = zsobol::permuted_index(s, pair);
                REQUIRE(image[v] < image.size());
                seen.insert(image[v]);
            }
            CHECK(seen.size() == image.size());
            for (uint32_t block = (bits & 1u) ? 2u : 4u; block <= image.size(); block *= 4)
                for (uint64_t b0 = 0; b0 < image.size(); b0 += block)
                    for (uint64_t v = b0; v < b0 + block; ++v)
                        REQUIRE(image[v] / block == image[b0] / block);
        }
    }
}

TEST_CASE("zsobol: each pixel's samples, and each aligned block of pixels', form a (0, m, 2)-net",
          "[sampler][fast]") {
    const uint32_t res = 16;
    for (uint32_t n : {1u, 2u, 4u, 8u, 16u})
        for (uint32_t pair : {0u, 1u, 6u, 29u})
            for (uint32_t block : {1u, 2u, 4u}) {
                INFO("spp " << n << ", pair " << pair << ", block " << block);
                // Points in each pixel's own square: the block's pixels together are one net
                // of block^2 * n points, each pixel's alone a net of n.
                for (uint32_t by = 0; by < res; by += block)
                    for (uint32_t bx = 0; bx < res; bx += block) {
                        std::vector<Point2> pts;
                        for (uint32_t y = by; y < by + block; ++y)
                            for (uint32_t x = bx; x < bx + block; ++x)
                                for (uint32_t i = 0; i < n; ++i)
                                    pts.push_back(zsample(x, y, res, i, n, 4, pair));
                        REQUIRE(is_02_net(pts));
                    }
            }
    // A pixel of a non-power-of-two count takes the first n of the next power's net.
    std::vector<Point2> six;
    for (uint32_t i = 0; i < 8; ++i) six.push_back(zsample(3, 5, res, i, 6, 4, 2));
    CHECK(is_02_net(six));
    // Every pass is its own randomisation.
    Point2 a, b;
    zsobol::sample2(zsobol::index_of(3, 5, res, res, 0, 4, 4, 0), 1, a.x, a.y);
    zsobol::sample2(zsobol::index_of(3, 5, res, res, 0, 4, 4, 1), 1, b.x, b.y);
    CHECK((a.x != b.x || a.y != b.y));
}

TEST_CASE("zsobol: pairs are uncorrelated and uniform, and neighbours' errors cancel",
          "[sampler][fast]") {
    const uint32_t res = 64;
    double sx = 0, sy = 0, sxy = 0, sxx = 0, syy = 0;
    double N = 0;
    for (uint32_t y = 0; y < res; ++y)
        for (uint32_t x = 0; x < res; ++x)
            for (uint32_t i = 0; i < 4; ++i) {
                zsobol::Index s = zsobol::index_of(x, y, res, res, i, 4, 21, 0);
                const double u = zsobol::sample1(s, 1, 0), v = zsobol::sample1(s, 2, 0);
                sx += u, sy += v, sxy += u * v, sxx += u * u, syy += v * v, N += 1;
            }
    const double corr = (sxy / N - sx / N * sy / N) /
                        std::sqrt((sxx / N - sx / N * sx / N) * (syy / N - sy / N * sy / N));
    INFO("correlation " << corr);
    CHECK(std::fabs(corr) < 0.03);
    CHECK(sx / N == Approx(0.5).epsilon(0.01));
    CHECK(sy / N == Approx(0.5).epsilon(0.01));

    // Blue noise: every pixel estimates the same smooth integral from its samples. With
    // padded Sobol' the pixels' errors are independent, so a 2 x 2 block's summed error has
    // 4x a pixel's variance; in Z-order the block's samples are one net and its errors cancel.
    auto f = [](float u, float v) { return std::sin(5.f * u + 1.f) * std::exp(v) + u * v * v; };
    const double exact = (std::cos(1.0) - std::cos(6.0)) / 5.0 * (std::exp(1.0) - 1.0) + 1.0 / 6.0;
    for (uint32_t pair : {0u, 9u})
        for (uint32_t spp : {1u, 4u}) {
            double var_pixel[2] = {0, 0}, var_block[2] = {0, 0};
            for (int zorder = 0; zorder < 2; ++zorder)
                for (uint32_t by = 0; by < res; by += 2)
                    for (uint32_t bx = 0; bx < res; bx += 2) {
                        double block = 0;
                        for (uint32_t y = by; y < by + 2; ++y)
                            for (uint32_t x = bx; x < bx + 2; ++x) {
                                double est = 0;
                                for (uint32_t i = 0; i < spp; ++i) {
                                    Point2 p;
                                    if (zorder)
                                        p = zsample(x, y, res, i, spp, 8, pair);
                                    else
                                        sobol::sample2(i, spp, 8, y * res + x, pair, p.x, p.y);
                                    est += f(p.x, p.y) / spp;
                                }
                                var_pixel[zorder] += (est - exact) * (est - exact);
                                block += est - exact;
                            }
                        var_block[zorder] += block * block;
                    }
            // Sums over the image: a block's variance over its pixels' (the 4 per block).
            const double sobol_ratio = var_block[0] / var_pixel[0];
            const double z_ratio = var_block[1] / var_pixel[1];
            INFO("pair " << pair << ", spp " << spp << ": block / 4 pixels' variance, sobol "
                         << sobol_ratio << ", zsobol " << z_ratio);
            CHECK(sobol_ratio > 0.7);
            CHECK(sobol_ratio < 1.3);
            CHECK(z_ratio < 0.3 * sobol_ratio);
        }
}

TEST_CASE("random stream keys are distinct", "[sampler][fast]") {
    // Two users of one key would draw the same numbers (core/rng_streams.h).
    std::set<uint64_t> keys;
    for (RandomStream s : kAllRandomStreams) CHECK(keys.insert(uint64_t(s)).second);
    CHECK(keys.size() == std::size(kAllRandomStreams));
}

TEST_CASE("Counter-based numbers drawn as a table equal rng::uniform's, bit for bit",
          "[sampler][kernel][fast]") {
    std::mt19937_64 g(11);
    const std::size_t n = 203;  // the table kernel reads and writes up to 208
    std::vector<uint64_t> keys((n + 7) / 8 * 8);
    for (uint64_t& k : keys) k = g();
    keys[0] = 0;
    keys[1] = ~0ull;
    const std::vector<uint64_t> dims = {0, 1, 7, 8, 63, 1000, uint64_t(~0ull - 1)};
    for (const uint64_t seed : {uint64_t(0), uint64_t(12345), uint64_t(~0ull)}) {
        const uint64_t prefix = rng::stream_prefix(seed, kPathStream);
        std::vector<float> simd(dims.size() * keys.size()), scalar(simd.size());
        kern::uniform_table(prefix, keys.data(), n, dims.data(), dims.size(), simd.data(),
                            keys.size());
        kern::uniform_table_scalar(prefix, keys.data(), n, dims.data(), dims.size(), scalar.data(),
                                   keys.size());
        std::size_t differ = 0, engine_differ = 0;
        double sum = 0.0;
        for (std::size_t d = 0; d < dims.size(); ++d)
            for (std::size_t i = 0; i < n; ++i) {
                const float a = simd[d * keys.size() + i];
                differ += a != scalar[d * keys.size() + i];
                engine_differ += a != rng::uniform(seed, kPathStream, keys[i], dims[d]);
                sum += a;
                CHECK((a >= 0.f && a < 1.f));
            }
        CHECK(differ == 0);
        CHECK(engine_differ == 0);
        CHECK(sum / double(n * dims.size()) == Approx(0.5).margin(0.03));
    }
}

TEST_CASE("Sobol' points drawn as a table equal sobol::sample2's, bit for bit",
          "[sampler][kernel][fast]") {
    std::mt19937_64 g(5);
    const std::size_t n = 301;  // the table kernel reads and writes up to 304
    const std::size_t stride = 304;
    std::vector<uint64_t> keys(stride);
    std::vector<uint32_t> index(stride), count(stride);
    for (std::size_t s = 0; s < stride; ++s) {
        keys[s] = g();
        // Counts of one point, powers of two, and counts that need cycle walking.
        const uint32_t counts[] = {1, 2, 3, 16, 17, 100, 1024, 4097, 1u << 20};
        count[s] = counts[s % 9];
        index[s] = uint32_t(g() % count[s]);
    }
    const std::vector<uint32_t> pairs = {0, 1, 2, 5, 33, 4000};
    for (const uint64_t seed : {uint64_t(0), uint64_t(77), uint64_t(~0ull)}) {
        std::vector<float> simd(2 * pairs.size() * stride), scalar(simd.size());
        kern::sobol::sample_table(seed, index.data(), count.data(), keys.data(), n, pairs.data(),
                                  pairs.size(), simd.data(), stride);
        kern::sobol::sample_table_scalar(seed, index.data(), count.data(), keys.data(), n,
                                         pairs.data(), pairs.size(), scalar.data(), stride);
        std::size_t differ = 0, engine_differ = 0;
        for (std::size_t p = 0; p < pairs.size(); ++p)
            for (std::size_t s = 0; s < n; ++s) {
                float x, y;
                sobol::sample2(index[s], count[s], seed, keys[s], pairs[p], x, y);
                const float a = simd[2 * p * stride + s], b = simd[(2 * p + 1) * stride + s];
                differ += a != scalar[2 * p * stride + s];
                differ += b != scalar[(2 * p + 1) * stride + s];
                engine_differ += a != x;
                engine_differ += b != y;
            }
        CHECK(differ == 0);
        CHECK(engine_differ == 0);
    }
}

TEST_CASE("Z-Sobol' points drawn as a table equal zsobol::sample2's, bit for bit",
          "[sampler][kernel][fast]") {
    std::mt19937_64 g(9);
    const std::size_t n = 205, stride = 208;
    std::vector<uint64_t> index(stride), keys(stride);
    std::vector<uint32_t> bits(stride);
    for (std::size_t s = 0; s < stride; ++s) {
        // Images of many sizes and sample counts: odd and even lengths (a lone lowest bit),
        // lengths that differ within a group of eight, indices past 32 bits.
        const uint32_t width = 1u + uint32_t(g() % 5000), height = 1u + uint32_t(g() % 3000);
        const uint32_t spp = 1u << (g() % 12);
        const zsobol::Index z =
            zsobol::index_of(uint32_t(g() % width), uint32_t(g() % height), width, height,
                             uint32_t(g() % spp), spp, g(), g() % 4);
        index[s] = s % 23 == 0 ? z.index | (uint64_t(g() % 1000) << 33) : z.index;
        bits[s] = s % 23 == 0 ? 43 : z.bits;
        keys[s] = z.key;
    }
    const std::vector<uint32_t> pairs = {0, 1, 2, 7, 40};
    std::vector<float> simd(2 * pairs.size() * stride), scalar(simd.size());
    kern::zsobol::sample_table(index.data(), bits.data(), keys.data(), n, pairs.data(),
                               pairs.size(), simd.data(), stride);
    kern::zsobol::sample_table_scalar(index.data(), bits.data(), keys.data(), n, pairs.data(),
                                      pairs.size(), scalar.data(), stride);
    std::size_t differ = 0, engine_differ = 0;
    for (std::size_t p = 0; p < pairs.size(); ++p)
        for (std::size_t s = 0; s < n; ++s) {
            float x, y;
            zsobol::sample2(zsobol::Index{index[s], bits[s], keys[s]}, pairs[p], x, y);
            const float a = simd[2 * p * stride + s], b = simd[(2 * p + 1) * stride + s];
            differ += (a != scalar[2 * p * stride + s]) + (b != scalar[(2 * p + 1) * stride + s]);
            engine_differ += (a != x) + (b != y);
        }
    CHECK(differ == 0);
    CHECK(engine_differ == 0);
}

TEST_CASE("Z-Sobol' table: a render pass's samples (one key) equal sample2's, bit for bit",
          "[sampler][kernel][fast]") {
    // The kernel's 16-lane path: the samples of one pass share a key. Images of several sizes
    // and sample counts (odd and even lengths, up to 32 bits), and groups that mix two images'
    // lengths (the per-lane digit mask).
    std::mt19937_64 g(21);
    const std::size_t n = 16 * 40;
    const uint64_t pass_key = zsobol::index_of(0, 0, 1, 1, 0, 1, 77, 3).key;
    const uint32_t sizes[][3] = {{256, 256, 16},    {640, 480, 8}, {1, 1, 1},
                                 {3840, 2160, 256}, {33, 17, 5},   {4096, 4096, 256},
                                 {200, 100, 2},     {7, 3000, 64}};
    for (const bool mixed : {false, true}) {
        std::vector<uint64_t> index(n), keys(n, pass_key);
        std::vector<uint32_t> bits(n);
        for (std::size_t s = 0; s < n; ++s) {
            const auto* sz = sizes[mixed ? (s * 7 + s / 3) % 8 : (s / 16) % 8];
            const uint32_t w = sz[0], h = sz[1], spp = sz[2];
            const zsobol::Index z = zsobol::index_of(uint32_t(g() % w), uint32_t(g() % h), w, h,
                                                     uint32_t(g() % spp), spp, 77, 3);
            REQUIRE(z.key == pass_key);
            REQUIRE(z.bits <= 32);
            index[s] = z.index;
            bits[s] = z.bits;
        }
        const std::vector<uint32_t> pairs = {0, 1, 5, 33};
        std::vector<float> table(2 * pairs.size() * n);
        kern::zsobol::sample_table(index.data(), bits.data(), keys.data(), n, pairs.data(),
                                   pairs.size(), table.data(), n);
        std::size_t differ = 0;
        for (std::size_t p = 0; p < pairs.size(); ++p)
            for (std::size_t s = 0; s < n; ++s) {
                float x, y;
                zsobol::sample2(zsobol::Index{index[s], bits[s], pass_key}, pairs[p], x, y);
                differ += (table[2 * p * n + s] != x) + (table[(2 * p + 1) * n + s] != y);
            }
        INFO("mixed lengths " << mixed);
        CHECK(differ == 0);
    }
}

TEST_CASE("Halton points drawn as a table equal halton::sample's, bit for bit",
          "[sampler][kernel][fast]") {
    // Indices from 0 to 2^32 - 1 (every digit position, trailing zero digits), each lane its
    // own key; dimensions of small and large bases, base 2, and past the table (counter-based).
    std::mt19937_64 g(13);
    const std::size_t n = 203, stride = 208;
    std::vector<uint32_t> index(stride);
    std::vector<uint64_t> keys(stride);
    for (std::size_t s = 0; s < stride; ++s) {
        const int kind = int(s % 4);
        index[s] = kind == 0   ? uint32_t(s % 7)
                   : kind == 1 ? uint32_t(g() % 64)
                   : kind == 2 ? uint32_t(g())
                               : 0xffffffffu - uint32_t(s);
        keys[s] = g();
    }
    const std::vector<uint32_t> dims = {0, 1, 2, 3, 4, 9, 30, 66, 100, 127, 128, 200};
    std::vector<float> simd(dims.size() * stride), scalar(simd.size());
    const uint64_t seed = 0x5eed;
    kern::halton::sample_table(seed, index.data(), keys.data(), n, dims.data(), dims.size(),
                               simd.data(), stride);
    kern::halton::sample_table_scalar(seed, index.data(), keys.data(), n, dims.data(), dims.size(),
                                      scalar.data(), stride);
    std::size_t differ = 0, engine_differ = 0, in_range = 0;
    for (std::size_t d = 0; d < dims.size(); ++d)
        for (std::size_t s = 0; s < n; ++s) {
            const float a = simd[d * stride + s];
            differ += a != scalar[d * stride + s];
            engine_differ += a != halton::sample(index[s], seed, keys[s], dims[d]);
            in_range += a >= 0.f && a < 1.f;
        }
    CHECK(differ == 0);
    CHECK(engine_differ == 0);
    CHECK(in_range == dims.size() * n);
}
