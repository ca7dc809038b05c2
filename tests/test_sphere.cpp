#include <catch2/catch.hpp>

#include "engine/scene/mesh.h"

using namespace foton;

TEST_CASE("ray/sphere intersection", "[sphere]") {
    const Sphere s{{0, 0, 0}, 2.f};
    float t = 0.f;
    SECTION("from outside: nearest root") {
        REQUIRE(intersect_sphere(s, {0, 0, -10}, {0, 0, 1}, 0.f, kInfinity, t));
        CHECK(t == Approx(8.f));
    }
    SECTION("from inside: the far root") {
        REQUIRE(intersect_sphere(s, {0, 0, 0}, {1, 0, 0}, 0.f, kInfinity, t));
        CHECK(t == Approx(2.f));
    }
    SECTION("unnormalised direction scales t") {
        REQUIRE(intersect_sphere(s, {0, 0, -10}, {0, 0, 2}, 0.f, kInfinity, t));
        CHECK(t == Approx(4.f));
    }
    SECTION("miss and tangent") {
        CHECK_FALSE(intersect_sphere(s, {0, 2.001f, -10}, {0, 0, 1}, 0.f, kInfinity, t));
        CHECK_FALSE(intersect_sphere(s, {0, 0, -10}, {0, 0, -1}, 0.f, kInfinity, t));
    }
    SECTION("t range respected") {
        CHECK_FALSE(intersect_sphere(s, {0, 0, -10}, {0, 0, 1}, 0.f, 7.9f, t));
        REQUIRE(intersect_sphere(s, {0, 0, -10}, {0, 0, 1}, 8.5f, kInfinity, t));
        CHECK(t == Approx(12.f));
    }
    SECTION("distant sphere keeps precision") {
        const Sphere far{{0, 0, 1e5f}, 1.f};
        REQUIRE(intersect_sphere(far, {0, 0, 0}, {0, 0, 1}, 0.f, kInfinity, t));
        CHECK(t == Approx(1e5f - 1.f).epsilon(1e-6));
    }
}
