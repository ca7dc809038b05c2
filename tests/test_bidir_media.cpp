// bdpt and vcm through participating media (transport/bidir/subpath_media.h) against
// volumetric path tracing: the foggy box (homogeneous fog, glass, two area lights) and the
// smoke grid (an interface sphere, a sky); single strategies with medium vertices on either
// side against each other; the same image for any thread count; what is refused.
#include <catch2/catch.hpp>
#include <string>

#include "engine/core/error.h"
#include "engine/scene/xml_loader.h"
#include "image_checks.h"
#include "media_util.h"
#include "test_util.h"

using namespace foton;
using test::check_means;

TEST_CASE("bdpt and vcm through fog converge to volpath's image on the foggy Cornell box",
          "[media][bidir][render]") {
    TestScene s = test::fog(24);
    const uint32_t e = test::effort();
    s.render.integrator = "volpath";
    const Film volpath = render_test(s, 1024 * e, 2, 3).film;
    for (const char* integrator : {"bdpt", "vcm"}) {
        INFO(integrator);
        s.render.integrator = integrator;
        check_means(test::masked_mean(render_test(s, 128 * e, 2, 3).film, volpath),
                    test::masked_mean(volpath, volpath), 0.03);
    }
}

TEST_CASE("bdpt's light samples and light tracing from medium vertices carry the same light",
          "[media][bidir][render]") {
    // Paths of one scattering vertex, in the fog or on a wall: strategy (1, 2) makes it a
    // camera vertex joined to a light sample, (2, 1) a light vertex joined to the camera. The
    // two sample the same paths (neither through the glass), each at full weight.
    TestScene s = test::fog(16);
    const uint32_t e = test::effort();
    s.render.max_depth = 1;
    auto alone = [&](int strategy_s, int strategy_t) {
        TestScene b = s;
        b.render.integrator = "bdpt";
        b.render.bidir.only_s = strategy_s;
        b.render.bidir.only_t = strategy_t;
        return render_test(b, 256 * e, 2, 5).film;
    };
    const Film nee = alone(1, 2), light = alone(2, 1);
    check_means(test::masked_mean(light, nee), test::masked_mean(nee, nee), 0.03);
}

TEST_CASE(
    "bdpt and vcm through a smoke grid agree with volpath, the same image for any thread "
    "count, emitting media and bpm refused",
    "[media][bidir][render]") {
    TestScene s = load_scene(test::source_path("scenes/smoke.xml"));
    s.set_resolution(24, 24);
    const uint32_t e = test::effort();
    s.render.integrator = "volpath";
    const Film volpath = render_test(s, 256 * e, 2, 3).film;
    for (const char* integrator : {"bdpt", "vcm"}) {
        INFO(integrator);
        s.render.integrator = integrator;
        check_means(test::image_mean(render_test(s, 64 * e, 2, 3).film), test::image_mean(volpath),
                    0.03);
    }

    TestScene f = test::fog(12);
    for (const char* integrator : {"bdpt", "vcm"}) {
        INFO(integrator);
        f.render.integrator = integrator;
        CHECK(render_test(f, 2, 1, 4).film.pixels == render_test(f, 2, 3, 4).film.pixels);
    }
    f.render.integrator = "bpm";
    CHECK_THROWS_WITH(render_test(f, 1), Catch::Contains("bpm") && Catch::Contains("media"));
    f.render.integrator = "bdpt";
    f.media[0].sigma_a = RGB{0.01f};
    f.media[0].Le = RGB{1.f};
    CHECK_THROWS_WITH(render_test(f, 1),
                      Catch::Contains("medium 'fog' emits, and bdpt starts light paths at lights "
                                      "only"));
}
