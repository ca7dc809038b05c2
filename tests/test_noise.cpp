// Perlin noise and pbrt-v4's noise textures (fbm, wrinkled, windy, marble).
#include <catch2/catch.hpp>
#include <cmath>

#include "engine/core/rng.h"
#include "engine/scene/noise.h"
#include "engine/scene/pbrt_loader.h"
#include "engine/scene/scene.h"

using namespace foton;

TEST_CASE("Perlin noise: zero on the lattice, bounded, continuous, centred", "[noise][fast]") {
    for (int i = -3; i <= 3; ++i)
        for (int j = -3; j <= 3; ++j)
            CHECK(perlin_noise({float(i), float(j), float(i + j)}) == Approx(0.f).margin(1e-6));
    double sum = 0.0, sum_abs = 0.0, worst_step = 0.0, largest = 0.0;
    const int n = 20000;
    for (int i = 0; i < n; ++i) {
        const Vec3 p{rng::uniform(21, 0, uint64_t(i), 0) * 40.f - 20.f,
                     rng::uniform(21, 1, uint64_t(i), 0) * 40.f - 20.f,
                     rng::uniform(21, 2, uint64_t(i), 0) * 40.f - 20.f};
        const float v = perlin_noise(p);
        sum += v;
        sum_abs += std::fabs(v);
        largest = std::max(largest, double(std::fabs(v)));
        // The gradient is bounded (a few units): a step of 1e-3 moves it by little.
        worst_step =
            std::max(worst_step, double(std::fabs(perlin_noise(p + Vec3{1e-3f, 0.f, 0.f}) - v)));
    }
    CHECK(largest <= 1.1);
    CHECK(sum_abs / n > 0.1);  // it varies
    CHECK(std::fabs(sum / n) < 0.02);
    CHECK(worst_step < 0.01);
    // The table repeats every 256 lattice cells, and huge coordinates stay finite.
    CHECK(perlin_noise({0.3f, 0.6f, 0.9f}) ==
          Approx(perlin_noise({256.3f, 0.6f, 0.9f})).margin(1e-4));
    CHECK(std::isfinite(perlin_noise({1e30f, -1e30f, 3.f})));
    // One octave of fbm is the noise; turbulence is never negative.
    const Vec3 q{1.3f, -2.7f, 0.4f};
    CHECK(fbm(q, 0.5f, 1) == Approx(perlin_noise(q)));
    CHECK(fbm(q, 0.5f, 2) == Approx(perlin_noise(q) + 0.5f * perlin_noise(q * 1.99f)));
    CHECK(turbulence(q, 0.5f, 8) > 0.f);
}

TEST_CASE("pbrt-v4: fbm, wrinkled and windy textures read the noise at the point",
          "[noise][pbrt][fast]") {
    const std::string text = R"(LookAt 0 0 5  0 0 0  0 1 0
Camera "perspective" "float fov" 40
WorldBegin
AttributeBegin
  Scale 3 3 3
  Texture "bumps" "float" "wrinkled" "integer octaves" 4 "float roughness" 0.6
AttributeEnd
Texture "cloud" "float" "fbm"
Texture "waves" "float" "windy"
Material "diffuse" "texture displacement" "bumps" Shape "sphere"
Material "conductor" "texture roughness" "cloud" Shape "sphere"
Material "diffuse" "texture displacement" "waves" Shape "sphere"
)";
    const Scene s = parse_pbrt_scene(text, "noise.pbrt", ".");
    const Texture& bumps = s.textures[std::size_t(s.materials[s.objects.at(0).material].bump)];
    const Vec3 p{1.f, 2.f, -0.5f};
    const TexPoint at{{0.f, 0.f}, p, {0.f, 0.f, 1.f}};
    // Declared under Scale 3: read at p / 3, with its octaves and roughness.
    CHECK(bumps.eval_float(s.texture_images, at) == Approx(turbulence(p * (1.f / 3.f), 0.6f, 4)));
    const Texture& waves = s.textures[std::size_t(s.materials[s.objects.at(2).material].bump)];
    CHECK(waves.eval_float(s.texture_images, at) ==
          Approx(std::fabs(fbm(p * 0.1f, 0.5f, 3)) * fbm(p, 0.5f, 6)));
    REQUIRE(s.materials[s.objects.at(1).material].num_float_params == 2);  // alpha x and y
    // A spectrum noise texture is an error, as in pbrt-v4.
    CHECK_THROWS_WITH(
        parse_pbrt_scene("WorldBegin\nTexture \"n\" \"spectrum\" \"fbm\"\nShape \"sphere\"",
                         "bad.pbrt", "."),
        Catch::Contains("bad.pbrt:2: 'fbm' is a float texture in pbrt-v4"));
}

TEST_CASE("pbrt-v4: the marble texture's veins follow its spline", "[noise][pbrt][fast]") {
    const std::string text = R"(WorldBegin
Texture "calm" "spectrum" "marble" "float variation" 0 "float scale" 2
Texture "veined" "spectrum" "marble"
Material "diffuse" "texture reflectance" "calm" Shape "sphere"
Material "diffuse" "texture reflectance" "veined" Shape "sphere"
)";
    const Scene s = parse_pbrt_scene(text, "marble.pbrt", ".");
    const Texture& calm = s.textures[std::size_t(s.materials[s.objects.at(0).material].texture)];
    auto at = [](float y) { return TexPoint{{0.f, 0.f}, {0.3f, y, -0.2f}, {0.f, 0.f, 1.f}}; };
    // Without variation t = (1 + sin(2 y)) / 2: the spline's middle control point at t = 1/2,
    // its ends (the light grey 0.58, 0.58, 0.6, times 1.5) at t = 0 and 1.
    const RGB mid = calm.eval(s.texture_images, at(0.f));
    CHECK(mid.r == Approx(0.75f));
    CHECK(mid.b == Approx(0.75f));
    for (float y : {-kPi / 4.f, kPi / 4.f}) {
        const RGB end = calm.eval(s.texture_images, at(y));
        CHECK(end.r == Approx(0.87f).epsilon(1e-4));
        CHECK(end.b == Approx(0.9f).epsilon(1e-4));
    }
    // With variation the veins wander: values stay within the spline's hull and vary.
    const Texture& veined = s.textures[std::size_t(s.materials[s.objects.at(1).material].texture)];
    float lo = 10.f, hi = 0.f;
    for (int i = 0; i < 2000; ++i) {
        const RGB c = veined.eval(s.texture_images, at(0.01f * float(i)));
        lo = std::min(lo, c.g);
        hi = std::max(hi, c.g);
    }
    CHECK(lo >= 1.5f * 0.2f - 1e-4f);
    CHECK(hi <= 1.5f * 0.6f + 1e-4f);
    CHECK(hi - lo > 0.2f);
    CHECK_THROWS_WITH(
        parse_pbrt_scene("WorldBegin\nTexture \"m\" \"float\" \"marble\"\nShape \"sphere\"",
                         "bad.pbrt", "."),
        Catch::Contains("bad.pbrt:2: 'marble' is a spectrum texture in pbrt-v4"));
}

TEST_CASE("pbrt-v4: bilerp and dots textures", "[noise][pbrt][texture][fast]") {
    const Scene s = parse_pbrt_scene(R"(LookAt 0 0 5  0 0 0  0 1 0
Camera "perspective" "float fov" 40
WorldBegin
Texture "ramp" "spectrum" "bilerp" "rgb v00" [0 0 0] "rgb v01" [0 1 0] "rgb v10" [1 0 0]
    "rgb v11" [1 1 1]
Texture "spots" "float" "dots" "float inside" 2 "float outside" 0.5 "float uscale" 4
    "float vscale" 4
Material "diffuse" "texture reflectance" "ramp" "texture displacement" "spots"
Shape "sphere"
)",
                                     "tex.pbrt", ".");
    const Material& m = s.materials[s.objects.at(0).material];
    const Texture& ramp = s.textures[std::size_t(m.texture)];
    const Texture& spots = s.textures[std::size_t(m.bump)];
    // Bilinear in (s, t): v10 at s = 1, v01 at t = 1; halfway a quarter of each corner.
    const RGB mid = ramp.eval(s.texture_images, TexPoint{0.25f, 0.75f});
    CHECK(mid.r == Approx(0.25f));
    CHECK(mid.g == Approx(0.75f));
    CHECK(mid.b == Approx(0.25f * 0.75f));
    // Dots: only the two values; never at a cell's corner (0.35 + 0.15 sqrt 2 < 0.5 sqrt 2);
    // over many cells some have dots, some not.
    int inside = 0, outside = 0;
    for (int i = 0; i < 200; ++i)
        for (int j = 0; j < 8; ++j) {
            // (s, t) = (i, j): a cell's centre, inside its dot whenever it has one (the dot
            // moves at most 0.15 each way).
            const float v =
                spots.eval_float(s.texture_images, TexPoint{float(i) / 4.f, float(j) / 4.f});
            REQUIRE((v == Approx(2.f) || v == Approx(0.5f)));
            (v > 1.f ? inside : outside)++;
            // A cell's corner (s, t half-integers) is outside every dot.
            CHECK(spots.eval_float(s.texture_images,
                                   TexPoint{(float(i) + 0.5f) / 4.f, (float(j) + 0.5f) / 4.f}) ==
                  Approx(0.5f));
        }
    CHECK(inside > 100);
    CHECK(outside > 100);
}
