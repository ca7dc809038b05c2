// The light tracer's shading kernel (kernels/importance_shade.h): SIMD bit for bit equal to
// its scalar twin on random vertices (Lambertian, Oren–Nayar and every glossy lobe, with and
// without Russian roulette), and the twin's connection to the eye and continuation equal to
// the light tracer's own arithmetic on the engine's BSDF in importance mode (Bsdf::f and
// Bsdf::sample, Veach's adjoint shading-normal factor) up to the lobes' polynomial rounding.
#include <catch2/catch.hpp>
#include <cmath>

#include "engine/core/warp.h"
#include "engine/scene/bsdf.h"
#include "kernels/importance_shade.h"
#include "shade_vertices.h"

using namespace foton;
using namespace foton::kern;
using test::make_glossy;
using test::random_vertices;
using test::Table;

namespace {

Vec3 get3(Table& t, uint32_t c, std::size_t i) {
    return {t.at(c, i), t.at(c + 1, i), t.at(c + 2, i)};
}

// Random light-path vertices: the eye where the diffuse tests put the light's point, the
// glossy lobes on most lanes.
Table importance_vertices(std::size_t n, uint32_t seed, std::vector<Bsdf>& bsdfs) {
    Table t = random_vertices(n, seed);
    make_glossy(t, n, seed + 7, bsdfs);
    return t;
}

}  // namespace

TEST_CASE("Importance shading lanes: SIMD equals its scalar twin bit for bit",
          "[kernel][shade][fast]") {
    const std::size_t n = 4099;
    for (const bool roulette : {false, true}) {
        std::vector<Bsdf> bsdfs;
        Table a = importance_vertices(n, roulette ? 41u : 42u, bsdfs);
        Table b = a;
        shade_importance(a.view(), n, roulette);
        shade_importance_scalar(b.view(), n, roulette);
        const test::TwinComparison r = test::compare_twin(a, b, n);
        const std::size_t i = r.first_bad_lane < n ? r.first_bad_lane : 0;
        INFO("first lane that differs: " << r.first_bad_lane << " kind " << a.at(kDvGlossKind, i));
        CHECK(r.validity_mismatches == 0);
        CHECK(r.bit_mismatches == 0);
        CHECK(r.shadows > n / 6);
        CHECK(r.shadows < n);
        CHECK(r.nexts > n / 5);
        CHECK(r.nexts < n);
    }
}

TEST_CASE("Importance shading lanes: the twin connects and continues as the light tracer",
          "[kernel][shade][fast]") {
    const std::size_t n = 6000;
    std::vector<Bsdf> bsdfs;
    Table t = importance_vertices(n, 555, bsdfs);
    shade_importance_scalar(t.view(), n, false);
    std::size_t connected = 0, continued = 0, disagree = 0, diffuse_only = 0;
    const BsdfContext ctx{true, Transport::Importance};
    for (std::size_t i = 0; i < n; ++i) {
        const Vec3 ns = get3(t, kDvNsx, i), ng = get3(t, kDvNgx, i), wl = get3(t, kDvWox, i);
        const Vec3 p = get3(t, kDvPx, i), eye = get3(t, kDvLpx, i);
        const warp::Frame frame(ns);
        const Vec3 wo = frame.to_local(wl);
        const RGB beta{t.at(kDvBetaR, i), t.at(kDvBetaG, i), t.at(kDvBetaB, i)};
        const float wl_ng = std::fabs(dot(wl, ng));
        const float adj = std::fabs(wo.z) / wl_ng;
        INFO("lane " << i << " kind " << t.at(kDvGlossKind, i));
        // The connection: LightTracer's value before the camera's importance.
        const Vec3 wc = normalize(eye - p);
        const float c_ng = dot(wc, ng);
        const RGB value =
            c_ng > 0.f ? beta * bsdfs[i].f(wo, frame.to_local(wc), ctx) * (adj * c_ng) : RGB{0.f};
        if (value.max_component() > 1e-20f) {
            CHECK(t.at(kDvShadowValid, i) == 1.f);
            CHECK(t.at(kDvSvR, i) == Approx(value.r).epsilon(2e-3).margin(1e-12));
            CHECK(t.at(kDvSvB, i) == Approx(value.b).epsilon(2e-3).margin(1e-12));
            CHECK(length(get3(t, kDvSdx, i) - wc) < 1e-5f);
            ++connected;
        } else if (value.is_black()) {
            CHECK(t.at(kDvShadowValid, i) == 0.f);
        }
        // The continuation: beta f adj |wi.ng| / pdf.
        BsdfSample s;
        const bool sampled =
            bsdfs[i].sample(wo, t.at(kDvUChoice, i), {t.at(kDvU0, i), t.at(kDvU1, i)}, ctx, s);
        const Vec3 wi = sampled ? frame.to_world(s.wi) : Vec3{};
        const float side = dot(wi, ng);
        const RGB nb = sampled ? beta * s.f * (adj * std::fabs(side) / s.pdf) : RGB{0.f};
        const bool engine_next = sampled && side > 0.f && !nb.is_black();
        const bool next = t.at(kDvNextValid, i) != 0.f;
        if (engine_next != next) {
            ++disagree;
            continue;
        }
        if (next) {
            CHECK(length(wi - get3(t, kDvNdx, i)) < 2e-4f);
            CHECK(t.at(kDvNbetaR, i) == Approx(nb.r).epsilon(2e-3).margin(1e-6));
            CHECK(t.at(kDvNbetaG, i) == Approx(nb.g).epsilon(2e-3).margin(1e-6));
            ++continued;
            diffuse_only += t.at(kDvGlossKind, i) == 0.f;
        }
    }
    INFO("connected " << connected << " continued " << continued << " disagree " << disagree);
    // Validity differs only where a polynomial and libm fall either side of a threshold.
    CHECK(disagree <= n / 500);
    CHECK(connected > n / 10);
    CHECK(continued > n / 5);
    CHECK(diffuse_only > n / 40);
}
