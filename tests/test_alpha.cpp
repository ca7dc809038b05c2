// Alpha cut-outs (Material::alpha, AlphaIntersector): every backend finds the same hits as
// brute force through checkerboard-masked and stochastic layers, rays pass the cut-out cells to
// what lies behind, a half-transparent layer stops half the rays, a sphere of alpha 0.3 stops
// 1 - 0.7^2 of those through its middle (entry and exit independent), a floor under a screen
// of alpha 0.5 receives half the light; the pbrt importer reads `alpha` as a float or an RGBA
// image's alpha; bad alpha fails at its line.
#include <catch2/catch.hpp>
#include <cmath>

#include <stb/stb_image_write.h>

#include "engine/accel/alpha_intersector.h"
#include "engine/accel/intersector.h"
#include "engine/core/error.h"
#include "engine/core/rng.h"
#include "engine/scene/pbrt_loader.h"
#include "test_util.h"

using namespace foton;

namespace {

// A floor at z = 0 and, above it, three screens over [-1, 1]^2: at z = 1 a checkerboard mask
// (4 x 4 cells, the even ones cut out), at z = 2 a constant alpha `a`, at z = 3 opaque but for
// a sphere of alpha 0.3 in front of it at z = 4.
std::string layers(float a) {
    auto quad = [](float z) {
        return "Shape \"trianglemesh\" \"point3 P\" [-1 -1 " + std::to_string(z) + "  1 -1 " +
               std::to_string(z) + "  1 1 " + std::to_string(z) + "  -1 1 " + std::to_string(z) +
               "] \"point2 uv\" [0 0  1 0  1 1  0 1] \"integer indices\" [0 1 2  0 2 3]\n";
    };
    return "LookAt 0 0 10  0 0 0  0 1 0\nCamera \"perspective\"\nWorldBegin\n"
           "Texture \"mask\" \"float\" \"checkerboard\" \"float uscale\" [4] \"float vscale\" [4]"
           " \"float tex1\" [0] \"float tex2\" [1]\n"
           "Material \"diffuse\"\n"
           "Shape \"trianglemesh\" \"point3 P\" [-9 -9 0  9 -9 0  9 9 0  -9 9 0]"
           " \"integer indices\" [0 1 2  0 2 3]\n"
           "AttributeBegin\nShape \"trianglemesh\" \"texture alpha\" \"mask\" " +
           quad(1.f).substr(std::string("Shape \"trianglemesh\" ").size()) +
           "AttributeEnd\nAttributeBegin\nShape \"trianglemesh\" \"float alpha\" [" +
           std::to_string(a) + "] " +
           quad(2.f).substr(std::string("Shape \"trianglemesh\" ").size()) + "AttributeEnd\n" +
           quad(3.f) +
           "AttributeBegin\nTranslate 0 0 4\nShape \"sphere\" \"float radius\" [0.5] "
           "\"float alpha\" [0.3]\nAttributeEnd\n";
}

}  // namespace

TEST_CASE("alpha: every backend finds brute force's hits through cut-out layers",
          "[alpha][accel][fast]") {
    const Scene s = parse_pbrt_scene(layers(0.5f), "a.pbrt", ".");
    RayBatch rays;
    // Rays aimed anywhere over the layers: from above the sphere, from between the screens
    // (down through the alpha screen, the mask, to the floor) and from under the mask, up.
    for (uint32_t i = 0; i < 3000; ++i) {
        const float x = 2.4f * rng::uniform(3, 0, i, 0) - 1.2f;
        const float y = 2.4f * rng::uniform(3, 0, i, 1) - 1.2f;
        const float z0 = i % 3 == 0 ? 6.f : i % 3 == 1 ? 2.5f : 0.5f;
        const Vec3 o{x * 0.3f, y * 0.3f, z0};
        const Vec3 target{x, y, i % 3 == 2 ? 5.f : 0.f};
        rays.push(o, normalize(target - o), 0.f, kInfinity, i);
    }
    TraceCounters c;
    const auto brute = make_intersector(s, AccelType::Brute);
    HitBatch want;
    brute->intersect(rays, want, c);
    std::vector<uint8_t> want_occ;
    RayBatch shadow = rays;
    for (std::size_t i = 0; i < shadow.size(); ++i) shadow.tmax[i] = 4.5f;
    brute->occluded(shadow, want_occ, c);
    // The mask: rays that end on the floor under the masked screen crossed a cut cell, those
    // that stop at z = 1 an opaque one.
    std::size_t at_mask = 0, through_mask = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        if (want.geom[i] == 1) ++at_mask;
        if (want.geom[i] == 0) ++through_mask;
    }
    CHECK(at_mask > 0);
    CHECK(through_mask > 0);
    for (const AccelType a : {AccelType::BruteSimd, AccelType::Grid, AccelType::Bvh,
                              AccelType::Embree, AccelType::Octree, AccelType::KdTree}) {
        const auto accel = make_intersector(s, a);
        HitBatch got;
        accel->intersect(rays, got, c);
        std::vector<uint8_t> occ;
        accel->occluded(shadow, occ, c);
        int wrong = 0;
        for (std::size_t i = 0; i < rays.size(); ++i) {
            wrong += got.geom[i] != want.geom[i] || got.prim[i] != want.prim[i] ||
                     (want.geom[i] != kNoHit && got.t[i] != Approx(want.t[i]).epsilon(1e-5));
            wrong += occ[i] != want_occ[i];
            Hit1 h;
            const bool hit = accel->intersect1(ray_at(rays, i), h, c);
            wrong += hit != (want.geom[i] != kNoHit) || h.geom != want.geom[i];
            wrong += accel->occluded1(ray_at(shadow, i), c) != (want_occ[i] != 0);
        }
        INFO(accel_name(a));
        CHECK(wrong == 0);
    }
}

TEST_CASE("alpha: the mask is where the texture says, stochastic layers stop their share",
          "[alpha][fast]") {
    for (const float a : {0.f, 0.5f, 1.f}) {
        const Scene s = parse_pbrt_scene(layers(a), "a.pbrt", ".");
        const auto accel = make_intersector(s, AccelType::Bvh);
        TraceCounters c;
        // Straight down through the mask's cells' centres: the even cells (tex1, 0) are cut.
        for (int i = 0; i < 4; ++i)
            for (int j = 0; j < 4; ++j) {
                const float x = -1.f + 0.25f + 0.5f * float(i), y = -1.f + 0.25f + 0.5f * float(j);
                Hit1 h;
                // From between the mask and the alpha screen, downwards.
                REQUIRE(accel->intersect1({x, y, 1.5f, 0.f, 0.f, -1.f, 0.f, kInfinity}, h, c));
                const bool even = (i + j) % 2 == 0;
                INFO("cell " << i << " " << j);
                CHECK(h.geom == (even ? 0u : 1u));
            }
        // Many rays straight down from z = 2.5 through the alpha screen: a share a stops there.
        RayBatch rays;
        const uint32_t n = 20000;
        for (uint32_t i = 0; i < n; ++i)
            rays.push({1.6f * rng::uniform(5, 0, i, 0) - 0.8f,
                       1.6f * rng::uniform(5, 0, i, 1) - 0.8f, 2.5f},
                      {0.f, 0.f, -1.f}, 0.f, kInfinity, i);
        HitBatch hits;
        accel->intersect(rays, hits, c);
        double stopped = 0.0;
        for (uint32_t i = 0; i < n; ++i) stopped += hits.geom[i] == 2 ? 1.0 : 0.0;
        INFO("alpha " << a);
        // Binomial: 5 standard deviations of 20,000 draws.
        CHECK(stopped / n == Approx(a).margin(5.0 * std::sqrt(0.25 / n)));
        // Down through the middle of the sphere of alpha 0.3: its entry and its exit each stop
        // 0.3, independently (as pbrt-v4's test of each from a new ray), 1 - 0.7^2 in all.
        rays.clear();
        for (uint32_t i = 0; i < n; ++i)
            rays.push({0.4f * rng::uniform(6, 0, i, 0) - 0.2f,
                       0.4f * rng::uniform(6, 0, i, 1) - 0.2f, 6.f},
                      {0.f, 0.f, -1.f}, 0.f, kInfinity, i);
        accel->intersect(rays, hits, c);
        double on_sphere = 0.0;
        for (uint32_t i = 0; i < n; ++i) on_sphere += hits.geom[i] == 4 ? 1.0 : 0.0;
        CHECK(on_sphere / n == Approx(0.51).margin(5.0 * std::sqrt(0.25 / n)));
    }
}

TEST_CASE("alpha: a floor under a screen of alpha 0.5 receives half the light", "[alpha]") {
    auto floor = [](const std::string& alpha) {
        return "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" [20]\n"
               "Film \"rgb\" \"integer xresolution\" [8] \"integer yresolution\" [8]\n"
               "Sampler \"independent\" \"integer pixelsamples\" [1]\n"
               "Integrator \"path\" \"integer maxdepth\" [1]\nWorldBegin\n"
               "LightSource \"distant\" \"point3 from\" [0 0 1] \"point3 to\" [0 0 0]"
               " \"rgb L\" [1 1 1]\n"
               "Material \"diffuse\" \"rgb reflectance\" [0.5 0.5 0.5]\n"
               "Shape \"trianglemesh\" \"point3 P\" [-50 -50 0  50 -50 0  50 50 0  -50 50 0]"
               " \"integer indices\" [0 1 2  0 2 3]\n"
               // The screen above the floor, seen edge-on by nothing: below the camera's view
               // it only shadows (its back faces the camera: it is placed behind the eye).
               "AttributeBegin\nMaterial \"diffuse\" \"rgb reflectance\" [0 0 0]\n"
               "Shape \"trianglemesh\" " +
               alpha +
               " \"point3 P\" [-50 -50 6  50 -50 6  50 50 6  -50 50 6]"
               " \"integer indices\" [0 1 2  0 2 3]\nAttributeEnd\n";
    };
    auto mean = [&](const std::string& alpha) {
        TestScene s(parse_pbrt_scene(floor(alpha), "f.pbrt", "."));
        const Film img = render_test(s, 256).film;
        double sum = 0.0;
        for (const RGB& p : img.pixels) sum += p.g;
        return sum / double(img.pixels.size());
    };
    const double open = mean("\"float alpha\" [0]"), half = mean("\"float alpha\" [0.5]");
    CHECK(open == Approx(0.5 / kPi).epsilon(1e-3));
    CHECK(half == Approx(0.5 * open).epsilon(0.03));
    CHECK(mean("\"float alpha\" [1]") == 0.0);
}

TEST_CASE("alpha: an RGBA image's alpha is the float texture, bad alpha fails at its line",
          "[alpha][fast]") {
    test::TempDir dir;
    // 2 x 1: an opaque texel and a transparent one.
    const unsigned char px[] = {255, 0, 0, 255, 0, 255, 0, 0};
    REQUIRE(stbi_write_png(dir.file("cut.png").c_str(), 2, 1, 4, px, 8) != 0);
    const std::string scene =
        "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\"\nWorldBegin\n"
        "Texture \"a\" \"float\" \"imagemap\" \"string filename\" \"" +
        dir.file("cut.png") +
        "\" \"string filter\" \"point\"\n"
        "Shape \"trianglemesh\" \"texture alpha\" \"a\" \"point3 P\" [-1 -1 0  1 -1 0  1 1 0  "
        "-1 1 0] \"point2 uv\" [0 0  1 0  1 1  0 1] \"integer indices\" [0 1 2  0 2 3]\n";
    const Scene s = parse_pbrt_scene(scene, "i.pbrt", ".");
    REQUIRE(s.materials.back().alpha_texture >= 0);
    const Texture& t = s.textures[std::size_t(s.materials.back().alpha_texture)];
    CHECK(t.eval_float(s.texture_images, {0.25f, 0.5f}) == Approx(1.f));
    CHECK(t.eval_float(s.texture_images, {0.75f, 0.5f}) == Approx(0.f));
    CHECK(alpha_hit_counts(s, 0, 0, 5.f, 0.1f, 0.05f, {-0.8f, 0.f, 5.f}, {0.f, 0.f, -1.f}, 0));
    CHECK_THROWS_WITH(
        parse_pbrt_scene("WorldBegin\nShape \"sphere\" \"float alpha\" [2]\n", "b.pbrt", "."),
        Catch::Contains("b.pbrt:2") && Catch::Contains("alpha"));
}
