// Light tracing through participating media against volumetric path tracing: the foggy box
// (homogeneous fog, glass, a spot light and a small area light) and the smoke grid, the same
// image for any thread count, and emitting media refused.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <string>

#include "engine/core/error.h"
#include "engine/scene/xml_loader.h"
#include "media_util.h"
#include "test_util.h"

using namespace foton;

namespace {

// The pixels where neither the small light (the brightest 3 % of `ref`) nor the glass ball
// (centre c, radius r) is in view: light tracing cannot join a light path to the eye through a
// specular surface, so what the eye sees through the glass is path tracing's alone.
std::vector<uint8_t> diffuse_view(const Scene& s, const Film& ref, const Vec3& c, float r) {
    std::vector<uint8_t> mask = test::below_brightest(ref);
    for (int y = 0; y < int(ref.height); ++y)
        for (int x = 0; x < int(ref.width); ++x) {
            const std::size_t i = std::size_t(y) * ref.width + std::size_t(x);
            bool glass = false;
            for (int k = 0; k < 5; ++k) {
                const float fx = float(x) + (k == 4 ? 0.5f : float(k & 1)),
                            fy = float(y) + (k == 4 ? 0.5f : float(k >> 1));
                Vec3 o, d;
                s.camera.generate(fx, fy, o, d);
                const Vec3 oc = c - o;
                const float along = dot(oc, d);
                glass |= along > 0.f && length_squared(oc - d * along) < (r + 5.f) * (r + 5.f);
            }
            if (glass) mask[i] = 0;
        }
    return mask;
}

// The pixels that see only the ground (the quad y = 0, |x|, |z| <= 6), through the smoke or
// not: the sky the eye sees directly, or through the smoke, is a path from an infinite light
// straight to the eye, which light paths (starting on a disc beyond the scene) never take.
std::vector<uint8_t> ground_view(const Scene& s, const Film& ref) {
    std::vector<uint8_t> mask(ref.pixels.size());
    for (int y = 0; y < int(ref.height); ++y)
        for (int x = 0; x < int(ref.width); ++x) {
            bool ground = true;
            for (int k = 0; k < 4; ++k) {
                Vec3 o, d;
                s.camera.generate(float(x + (k & 1)), float(y + (k >> 1)), o, d);
                const float t = d.y < 0.f ? -o.y / d.y : -1.f;
                const Vec3 p = o + d * t;
                ground &= t > 0.f && std::fabs(p.x) < 6.f && std::fabs(p.z) < 6.f;
            }
            mask[std::size_t(y) * ref.width + std::size_t(x)] = ground ? 1 : 0;
        }
    return mask;
}

}  // namespace

TEST_CASE("light tracing through fog converges to volpath's image on the foggy Cornell box",
          "[media][render]") {
    TestScene s = test::fog(24);
    const uint32_t e = test::effort();
    s.render.integrator = "volpath";
    const Film volpath = render_test(s, 1024 * e, 2, 3).film;
    const std::vector<uint8_t> mask = diffuse_view(s, volpath, {170, 260, 190}, 90);
    const RGB ref = compare_images(volpath, volpath, &mask).mean_a;
    s.render.integrator = "light";
    const Film light = render_test(s, 256 * e, 2, 3).film;
    const RGB got = compare_images(light, volpath, &mask).mean_a;
    INFO("volpath " << ref.r << " " << ref.g << " " << ref.b << ", light " << got.r << " " << got.g
                    << " " << got.b);
    CHECK(got.r == Approx(ref.r).epsilon(0.03));
    CHECK(got.g == Approx(ref.g).epsilon(0.03));
    CHECK(got.b == Approx(ref.b).epsilon(0.03));
}

TEST_CASE(
    "light tracing through a smoke grid agrees with volpath, the same image for any thread "
    "count, emitting media refused",
    "[media][render]") {
    TestScene s = load_scene(test::source_path("scenes/smoke.xml"));
    s.set_resolution(24, 24);
    const uint32_t e = test::effort();
    s.render.integrator = "volpath";
    const Film volpath = render_test(s, 256 * e, 2, 3).film;
    const std::vector<uint8_t> mask = ground_view(s, volpath);
    CHECK(std::count(mask.begin(), mask.end(), 1) > 150);
    const RGB ref = compare_images(volpath, volpath, &mask).mean_a;
    s.render.integrator = "light";
    const RGB got = compare_images(render_test(s, 256 * e, 2, 3).film, volpath, &mask).mean_a;
    INFO("volpath " << ref.r << " " << ref.g << " " << ref.b << ", light " << got.r << " " << got.g
                    << " " << got.b);
    CHECK(got.r == Approx(ref.r).epsilon(0.03));
    CHECK(got.g == Approx(ref.g).epsilon(0.03));
    CHECK(got.b == Approx(ref.b).epsilon(0.03));
    TestScene f = test::fog(16);
    f.render.integrator = "light";
    CHECK(render_test(f, 4, 1, 4).film.pixels == render_test(f, 4, 3, 4).film.pixels);
    f.media[0].sigma_a = RGB{0.01f};
    f.media[0].Le = RGB{1.f};
    try {
        render_test(f, 1);
        FAIL("rendered");
    } catch (const InputError& err) {
        CHECK(std::string(err.what())
                  .find("medium 'fog' emits, and light paths start at lights "
                        "only") != std::string::npos);
    }
}
