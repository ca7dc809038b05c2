// The bilinear 2D warp with conditioning parameters (engine/core/warp_2d.h) and the tensor
// file reader (engine/core/tensor_file.h), the two pieces of the RGL measured materials:
// samples follow the density (chi-square), invert undoes sample, densities agree with eval,
// parameters interpolate between grids, and tensor files read back what was written, bad
// ones named.
#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "chi_square.h"
#include "engine/core/error.h"
#include "engine/core/rng.h"
#include "engine/core/tensor_file.h"
#include "engine/core/warp_2d.h"
#include "tensor_writer.h"
#include "test_util.h"

using namespace foton;

namespace {

std::vector<float> random_grid(int w, int h, uint64_t seed) {
    std::vector<float> g(std::size_t(w * h));
    for (std::size_t i = 0; i < g.size(); ++i)
        g[i] = 0.05f + rng::uniform(seed, 2, i, 0) * (i % 3 == 0 ? 4.f : 1.f);
    return g;
}

// The warp's density integrated over [x0, x1) x [y0, y1) by a midpoint rule.
double mass(const Warp2D& w, double x0, double x1, double y0, double y1, const float* param) {
    const int n = 12;
    double sum = 0.0;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i)
            sum += w.eval(
                {float(x0 + (i + 0.5) * (x1 - x0) / n), float(y0 + (j + 0.5) * (y1 - y0) / n)},
                param);
    return sum * (x1 - x0) * (y1 - y0) / (n * n);
}

// Chi-square of 100,000 samples over 10 x 8 bins, and the round trip through invert().
void check_warp(const Warp2D& w, const float* param, uint64_t seed) {
    const int bx = 10, by = 8, samples = 100000;
    std::vector<double> count(bx * by, 0.0);
    float worst_round_trip = 0.f, worst_pdf = 0.f;
    for (int s = 0; s < samples; ++s) {
        const Point2 u{rng::uniform(seed, 1, uint64_t(s), 0),
                       rng::uniform(seed, 1, uint64_t(s), 1)};
        const Warp2D::Result r = w.sample(u, param);
        REQUIRE(r.p.x >= 0.f);
        REQUIRE(r.p.x <= 1.f);
        REQUIRE(r.p.y >= 0.f);
        REQUIRE(r.p.y <= 1.f);
        count[std::size_t(std::min(by - 1, int(r.p.y * by)) * bx +
                          std::min(bx - 1, int(r.p.x * bx)))] += 1;
        worst_pdf = std::max(worst_pdf, std::fabs(r.pdf - w.eval(r.p, param)) / r.pdf);
        const Warp2D::Result back = w.invert(r.p, param);
        worst_round_trip =
            std::max({worst_round_trip, std::fabs(back.p.x - u.x), std::fabs(back.p.y - u.y)});
        worst_pdf = std::max(worst_pdf, std::fabs(back.pdf - r.pdf) / r.pdf);
    }
    double chi2 = 0.0, total = 0.0;
    for (int j = 0; j < by; ++j)
        for (int i = 0; i < bx; ++i) {
            const double m = mass(w, double(i) / bx, double(i + 1) / bx, double(j) / by,
                                  double(j + 1) / by, param);
            total += m;
            const double e = samples * m;
            const double o = count[std::size_t(j * bx + i)];
            chi2 += (o - e) * (o - e) / e;
        }
    const double p = test::gamma_q(0.5 * (bx * by - 1), 0.5 * chi2);
    INFO("chi2 " << chi2 << " p " << p << ", round trip " << worst_round_trip << ", pdf "
                 << worst_pdf);
    CHECK(p > 1e-3);
    CHECK(worst_round_trip < 2e-4f);
    CHECK(worst_pdf < 1e-3f);
    CHECK(total == Approx(1.0).epsilon(2e-3));
}

}  // namespace

TEST_CASE("warp 2D: samples follow the bilinear density, invert undoes sample", "[warp][fast]") {
    const std::vector<float> g = random_grid(7, 5, 11);
    const Warp2D w(g.data(), 7, 5, {});
    check_warp(w, nullptr, 3);
    // Without the sampling tables and unnormalised, eval is the data interpolated.
    const Warp2D raw(g.data(), 7, 5, {}, false, false);
    CHECK(raw.eval({0.f, 0.f}) == Approx(g[0]));
    CHECK(raw.eval({1.f / 6.f, 0.25f}) == Approx(g[1 * 7 + 1]));
    CHECK(raw.eval({1.f / 12.f, 0.f}) == Approx(0.5f * (g[0] + g[1])));
}

TEST_CASE("warp 2D: parameters select and interpolate the grids", "[warp][fast]") {
    // Two parameters of 3 and 2 nodes: six grids, the last parameter fastest.
    const int w = 6, h = 5;
    std::vector<float> all;
    for (int k = 0; k < 6; ++k) {
        const std::vector<float> g = random_grid(w, h, 20 + uint64_t(k));
        all.insert(all.end(), g.begin(), g.end());
    }
    const Warp2D warp(all.data(), w, h, {{0.f, 0.5f, 2.f}, {-1.f, 1.f}});
    CHECK(warp.params() == 2);
    // At nodes: the grid there alone (grid k = 2 a + b for nodes a, b).
    const float at_node[2] = {0.5f, 1.f};
    const Warp2D alone(all.data() + std::size_t(3 * w * h), w, h, {});
    for (const Point2 u : {Point2{0.1f, 0.2f}, Point2{0.7f, 0.9f}, Point2{0.45f, 0.03f}}) {
        const Warp2D::Result a = warp.sample(u, at_node), b = alone.sample(u);
        CHECK(a.p.x == Approx(b.p.x).margin(1e-5));
        CHECK(a.p.y == Approx(b.p.y).margin(1e-5));
        CHECK(a.pdf == Approx(b.pdf).epsilon(1e-4));
    }
    // Between nodes: the normalised grids blended, sampled exactly.
    const float between[2] = {1.25f, 0.f};
    const Warp2D g10(all.data() + std::size_t(2 * w * h), w, h, {}),
        g11(all.data() + std::size_t(3 * w * h), w, h, {}),
        g20(all.data() + std::size_t(4 * w * h), w, h, {}),
        g21(all.data() + std::size_t(5 * w * h), w, h, {});
    const Point2 p{0.33f, 0.61f};
    const float t = (1.25f - 0.5f) / 1.5f;
    const float want =
        (1.f - t) * 0.5f * (g10.eval(p) + g11.eval(p)) + t * 0.5f * (g20.eval(p) + g21.eval(p));
    CHECK(warp.eval(p, between) == Approx(want).epsilon(1e-5));
    check_warp(warp, between, 5);
    // Beyond the nodes: the end grids.
    const float beyond[2] = {9.f, 1.f};
    CHECK(warp.eval(p, beyond) == Approx(g21.eval(p)).epsilon(1e-5));
}

TEST_CASE("tensor files: fields read back, malformed files are bad input",
          "[warp][bad-input][fast]") {
    const std::vector<float> theta{0.f, 0.5f, 1.f}, grid = random_grid(4, 3, 7);
    const std::string good = test::tensor_bytes(
        {test::float_tensor("theta_i", {3}, theta), test::float_tensor("ndf", {3, 4}, grid)});
    const TensorFile f = parse_tensor_file(good, "m.bsdf");
    CHECK(f.fields.size() == 2);
    const TensorField& ndf = f.field("ndf", 2);
    CHECK(ndf.shape == std::vector<uint64_t>{3, 4});
    CHECK(ndf.floats("m.bsdf", "ndf") == grid);
    CHECK(f.field("theta_i", 1).floats("m.bsdf", "theta_i") == theta);
    auto error = [](const std::string& bytes, auto&& use) -> std::string {
        try {
            use(parse_tensor_file(bytes, "m.bsdf"));
        } catch (const InputError& e) {
            return e.what();
        }
        return "";
    };
    auto nothing = [](const TensorFile&) {};
    CHECK_THAT(error(good, [](const TensorFile& t) { t.field("vndf", 4); }),
               Catch::Contains("m.bsdf: tensor file has no field 'vndf'"));
    CHECK_THAT(error(good, [](const TensorFile& t) { t.field("ndf", 3); }),
               Catch::Contains("'ndf' has 2 dimensions, not 3"));
    CHECK_THAT(error("tensor_fil", nothing), Catch::Contains("ends early"));
    CHECK_THAT(error("not_a_tensor" + good.substr(12), nothing), Catch::Contains("header"));
    std::string v2 = good;
    v2[12] = 2;
    CHECK_THAT(error(v2, nothing), Catch::Contains("version 2.0"));
    CHECK_THAT(error(good.substr(0, good.size() - 4), nothing),
               Catch::Contains("beyond the file's end"));
    CHECK_THAT(error(good.substr(0, 30), nothing), Catch::Contains("ends early"));
    // Every truncation is an error, never a crash.
    for (std::size_t n = 0; n < good.size(); ++n)
        CHECK_FALSE(error(good.substr(0, n), nothing).empty());
}
