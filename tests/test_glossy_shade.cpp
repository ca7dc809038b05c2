// The glossy lobes of the diffuse shading kernel (kernels/glossy_lanes.h): the log2/exp2
// polynomials they use against libm, the SIMD kernel bit for bit equal to its scalar twin on
// random vertices carrying Phong, Beckmann, Blinn, Ashikhmin–Shirley and GGX lobes (alone or
// beside a Lambertian or Oren–Nayar lobe, in either order, with each Fresnel term), and the
// twin's continuation and light sample equal to the engine's Bsdf::sample, f and pdf up to
// the polynomials' rounding.
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "engine/core/warp.h"
#include "engine/scene/bsdf.h"
#include "kernels/diffuse_shade.h"
#include "kernels/glossy_math.h"
#include "shade_vertices.h"

using namespace foton;
using namespace foton::kern;
using test::make_glossy;
using test::random_unit;
using test::random_vertices;
using test::Table;

namespace {

Vec3 get3(Table& t, uint32_t c, std::size_t i) {
    return {t.at(c, i), t.at(c + 1, i), t.at(c + 2, i)};
}

}  // namespace

TEST_CASE("Glossy math: log2, exp2 and pow polynomials against libm", "[kernel][shade][fast]") {
    std::mt19937 g(5);
    std::uniform_real_distribution<float> u01(0.f, 1.f);
    double worst_log = 0.0, worst_exp = 0.0, worst_pow = 0.0;
    for (int k = 0; k < 200000; ++k) {
        // Arguments over the whole normal range and its edges.
        const float x = std::ldexp(0.5f + 0.5f * u01(g), -int(126.f * u01(g)));
        const double l = std::log2(double(x));
        worst_log = std::max(worst_log, std::fabs(log2_poly(x) - l) / std::max(1.0, std::fabs(l)));
        const float y = -125.f + 130.f * u01(g);
        const double e = std::exp2(double(y));
        worst_exp = std::max(worst_exp, std::fabs(exp2_poly(y) - e) / e);
        // Cosines to exponents as the lobes raise them: the product's own rounding grows
        // with |y log2 x|, libm's as ours.
        const float c = u01(g), n = 1.f + 2000.f * u01(g) * u01(g);
        const double p = std::pow(double(c), double(n));
        if (p > 1e-30) {
            const double scale = 4.0 + std::fabs(double(n) * std::log2(double(c)));
            worst_pow = std::max(worst_pow, std::fabs(pow_poly(c, n) - p) / (p * scale));
        }
    }
    INFO("log2 " << worst_log << " exp2 " << worst_exp << " pow " << worst_pow);
    CHECK(worst_log < 3e-7);
    CHECK(worst_exp < 3e-7);
    CHECK(worst_pow < 3e-7);
    // The exact points and the edges.
    CHECK(log2_poly(1.f) == 0.f);
    CHECK(log2_poly(0.25f) == -2.f);
    CHECK(exp2_poly(0.f) == 1.f);
    CHECK(exp2_poly(-3.f) == 0.125f);
    CHECK(exp2_poly(-127.f) == 0.f);
    CHECK(pow_poly(0.f, 3.f) == 0.f);
    CHECK(pow_poly(1.f, 1e6f) == 1.f);
    CHECK(exp_poly(-1.f) == Approx(std::exp(-1.0)).epsilon(3e-7));
    CHECK(log_poly(0.5f) == Approx(std::log(0.5)).epsilon(3e-7));
}

TEST_CASE("Glossy shading lanes: SIMD equals its scalar twin bit for bit",
          "[kernel][shade][fast]") {
    const std::size_t n = 4099;
    for (const DiffuseMis mis : {DiffuseMis::Balance, DiffuseMis::Power, DiffuseMis::Maximum}) {
        for (const bool roulette : {false, true}) {
            Table a = random_vertices(n, 31u + uint32_t(mis));
            std::vector<Bsdf> bsdfs;
            make_glossy(a, n, 77u + uint32_t(mis), bsdfs);
            Table b = a;
            const DiffuseRules rules{mis, roulette};
            shade_diffuse(a.view(), n, rules);
            shade_diffuse_scalar(b.view(), n, rules);
            const test::TwinComparison r = test::compare_twin(a, b, n);
            const std::size_t i = r.first_bad_lane < n ? r.first_bad_lane : 0;
            INFO("first lane that differs: " << r.first_bad_lane << " kind "
                                             << a.at(kDvGlossKind, i) << " first "
                                             << a.at(kDvGlossFirst, i));
            CHECK(r.validity_mismatches == 0);
            CHECK(r.bit_mismatches == 0);
            CHECK(r.shadows > n / 6);
            CHECK(r.shadows < n);
            CHECK(r.nexts > n / 4);
            CHECK(r.nexts < n);
        }
    }
}

TEST_CASE("Glossy shading lanes: the twin samples and weighs as the engine's BSDF",
          "[kernel][shade][fast]") {
    const std::size_t n = 6000;
    Table t = random_vertices(n, 123);
    std::vector<Bsdf> bsdfs;
    make_glossy(t, n, 321, bsdfs);
    // The light samples as given (the kernel's own light sampling is the diffuse tests').
    for (std::size_t i = 0; i < n; ++i) t.at(kDvLkind, i) = 0.f;
    shade_diffuse_scalar(t.view(), n, DiffuseRules{DiffuseMis::Balance, false});
    std::size_t compared = 0, lit = 0, disagree = 0, per_kind[5] = {0, 0, 0, 0, 0};
    for (std::size_t i = 0; i < n; ++i) {
        if (t.at(kDvGlossKind, i) == 0.f) continue;
        const Vec3 ns = get3(t, kDvNsx, i), ng = get3(t, kDvNgx, i), wo = get3(t, kDvWox, i);
        const warp::Frame frame(ns);
        const Vec3 wo_l = frame.to_local(wo);
        const RGB beta{t.at(kDvBetaR, i), t.at(kDvBetaG, i), t.at(kDvBetaB, i)};
        const BsdfContext ctx{};
        // The continuation.
        BsdfSample s;
        const bool sampled =
            bsdfs[i].sample(wo_l, t.at(kDvUChoice, i), {t.at(kDvU0, i), t.at(kDvU1, i)}, ctx, s);
        const Vec3 wi = sampled ? frame.to_world(s.wi) : Vec3{};
        const RGB nb = sampled ? beta * s.f * (std::fabs(s.wi.z) / s.pdf) : RGB{0.f};
        const bool engine_next = sampled && dot(wi, ng) > 0.f && !nb.is_black();
        const bool next = t.at(kDvNextValid, i) != 0.f;
        if (engine_next != next) {
            ++disagree;
            continue;
        }
        if (next) {
            const Vec3 k = get3(t, kDvNdx, i);
            INFO("lane " << i << " kind " << t.at(kDvGlossKind, i));
            CHECK(length(wi - k) < 2e-4f);
            CHECK(t.at(kDvNpdf, i) == Approx(s.pdf).epsilon(2e-3).margin(1e-6));
            CHECK(t.at(kDvNbetaR, i) == Approx(nb.r).epsilon(2e-3).margin(1e-6));
            CHECK(t.at(kDvNbetaB, i) == Approx(nb.b).epsilon(2e-3).margin(1e-6));
            ++compared;
            ++per_kind[std::size_t(t.at(kDvGlossKind, i))];
        }
        // The light sample: f, pdf and the balance heuristic's weight.
        const Vec3 lw = get3(t, kDvLwx, i);
        const float pl = t.at(kDvLightPdf, i);
        if (pl > 0.f && dot(lw, ng) > 0.f) {
            const Vec3 wl = frame.to_local(lw);
            const RGB f = bsdfs[i].f(wo_l, wl, ctx);
            const float pb = bsdfs[i].pdf(wo_l, wl, ctx);
            const float w = t.at(kDvLightFull, i) != 0.f ? 1.f : pl / (pl + pb);
            const RGB li{t.at(kDvLiR, i), t.at(kDvLiG, i), t.at(kDvLiB, i)};
            const RGB value = beta * f * li * (std::fabs(wl.z) * w / pl);
            if (!value.is_black() && value.max_component() > 1e-20f) {
                CHECK(t.at(kDvShadowValid, i) == 1.f);
                CHECK(t.at(kDvSvR, i) == Approx(value.r).epsilon(2e-3).margin(1e-12));
                CHECK(t.at(kDvSvG, i) == Approx(value.g).epsilon(2e-3).margin(1e-12));
                ++lit;
            }
        }
    }
    INFO("compared " << compared << " lit " << lit << " disagree " << disagree);
    // Validity differs only where a polynomial and libm fall either side of a threshold.
    CHECK(disagree <= n / 500);
    CHECK(compared > n / 5);
    CHECK(lit > n / 10);
    for (std::size_t k = 1; k <= 4; ++k) CHECK(per_kind[k] > n / 50);
}
