#include <catch2/catch.hpp>

#include "engine/core/optics.h"

using namespace foton;

TEST_CASE("Fresnel reflectance of a dielectric", "[optics][fast]") {
    // Normal incidence: ((n - 1) / (n + 1))^2.
    CHECK(fresnel_dielectric(1.f, 1.f, 1.5f) == Approx(0.04f));
    CHECK(fresnel_dielectric(1.f, 1.5f, 1.f) == Approx(0.04f));
    CHECK(fresnel_dielectric(1.f, 1.f, 1.333f) == Approx(0.0204f).epsilon(1e-2));
    // Brewster's angle: the parallel component vanishes, R = r_perp^2 / 2.
    const float brewster = std::atan(1.5f);
    const float rb = fresnel_dielectric(std::cos(brewster), 1.f, 1.5f);
    CHECK(rb == Approx(0.5f * 0.147929f).epsilon(1e-3));  // r_perp = (1-n^2)/(1+n^2) = -0.3846
    // Grazing incidence reflects everything.
    CHECK(fresnel_dielectric(0.f, 1.f, 1.5f) == Approx(1.f));
    // 45 degrees on glass: 0.0502 (s 0.0920, p 0.0085).
    CHECK(fresnel_dielectric(std::cos(kPi / 4), 1.f, 1.5f) == Approx(0.0502f).epsilon(2e-3));
    // Total internal reflection beyond the critical angle asin(1 / 1.5) = 41.8 degrees.
    CHECK(fresnel_dielectric(std::cos(45.f * kPi / 180.f), 1.5f, 1.f) == 1.f);
    CHECK(fresnel_dielectric(std::cos(40.f * kPi / 180.f), 1.5f, 1.f) < 1.f);
}

TEST_CASE("reflection and refraction directions, total internal reflection", "[optics][fast]") {
    const Vec3 n{0, 1, 0};
    const Vec3 d = normalize(Vec3{1, -1, 0});
    const Vec3 r = reflect(d, n);
    CHECK(r.x == Approx(d.x));
    CHECK(r.y == Approx(-d.y));
    // Snell: sin_t = sin_i / 1.5 for 45 degrees.
    Vec3 t;
    REQUIRE(refract(d, n, 1.f / 1.5f, t));
    CHECK(length(t) == Approx(1.f));
    CHECK(t.x == Approx(std::sin(kPi / 4) / 1.5f));
    CHECK(t.y < 0.f);
    CHECK(t.z == Approx(0.f).margin(1e-7));
    // Normal incidence passes straight through.
    REQUIRE(refract(Vec3{0, -1, 0}, n, 1.f / 1.5f, t));
    CHECK(t.y == Approx(-1.f));
    // From glass to air at 45 degrees: beyond the critical angle.
    CHECK_FALSE(refract(d, n, 1.5f, t));
    // Just inside the critical angle it still refracts, almost grazing.
    const float crit = std::asin(1.f / 1.5f) - 1e-3f;
    REQUIRE(refract(Vec3{std::sin(crit), -std::cos(crit), 0}, n, 1.5f, t));
    CHECK(t.x > 0.99f);
}
