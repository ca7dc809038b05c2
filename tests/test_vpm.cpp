// Volumetric photon mapping (vpm) against volumetric path tracing, and the medium a light path
// starts in.
#include <algorithm>
#include <catch2/catch.hpp>
#include <string>
#include <vector>

#include "engine/core/error.h"
#include "engine/film/metrics.h"
#include "engine/scene/xml_loader.h"
#include "engine/transport/common/medium_locate.h"
#include "media_util.h"
#include "test_util.h"

using namespace foton;

using test::fog;
using test::image_mean;
using test::masked_mean;

TEST_CASE("a point's medium is found by walking from the camera", "[media][fast]") {
    // A box of fog (interface quad in front of the camera) and, inside it, a glass ball of ink.
    TestScene s = fog(8);
    const auto acc = make_intersector(s, AccelType::Bvh);
    CHECK(s.camera_medium == kNoMedium);
    CHECK(locate_medium(s, *acc, {278, 277, -400}) == kNoMedium);  // in front of the box
    CHECK(locate_medium(s, *acc, {300, 300, 300}) == 0);           // in the room's fog
    CHECK(locate_medium(s, *acc, {170, 470, 190}) == 0);           // the small light's centre
    // Behind the back wall there is no boundary: the walk passes the wall and stays in fog
    // (the box is closed only by the front quad; nothing says otherwise).
    CHECK(locate_medium(s, *acc, {300, 300, 700}) == 0);
}

TEST_CASE("vpm converges to volpath's image on the foggy Cornell box", "[media][render]") {
    TestScene s = fog(24);
    const uint32_t e = test::effort();
    s.render.integrator = "volpath";
    const Film volpath = render_test(s, 1024 * e, 2, 3).film;
    const RGB ref = masked_mean(volpath, volpath);
    TestScene v = load_scene(test::source_path("scenes/cornell-fog.xml"),
                             {{"type", "vpm"}, {"photons_per_pass", "20000"}});
    v.set_resolution(24, 24);
    const RGB got = masked_mean(render_test(v, 48 * e, 2, 3).film, volpath);
    INFO("volpath " << ref.r << " " << ref.g << " " << ref.b << ", vpm " << got.r << " " << got.g
                    << " " << got.b);
    // The radii's bias shrinks with the passes; 48 passes leave about 2 % (the volume estimate
    // near the walls, whose ball reaches beyond the fog, is low).
    CHECK(got.r == Approx(ref.r).epsilon(0.04));
    CHECK(got.g == Approx(ref.g).epsilon(0.04));
    CHECK(got.b == Approx(ref.b).epsilon(0.04));
}

TEST_CASE("vpm without media converges to the path tracer's image", "[media][render]") {
    TestScene s = load_scene(test::source_path("scenes/cornell-diffuse.xml"));
    s.set_resolution(24, 24);
    s.render.integrator = "path";
    const RGB ref = image_mean(render_test(s, 256, 2, 5).film);
    TestScene v = load_scene(test::source_path("scenes/cornell-diffuse.xml"),
                             {{"type", "vpm"}, {"photons_per_pass", "20000"}});
    v.set_resolution(24, 24);
    const RGB got = image_mean(render_test(v, 32, 2, 5).film);
    INFO("path " << ref.r << " " << ref.g << " " << ref.b << ", vpm " << got.r << " " << got.g
                 << " " << got.b);
    CHECK(got.r == Approx(ref.r).epsilon(0.04));
    CHECK(got.g == Approx(ref.g).epsilon(0.04));
    CHECK(got.b == Approx(ref.b).epsilon(0.04));
}

TEST_CASE("vpm: the same image for any thread count, and emitting media refused",
          "[media][render]") {
    TestScene v = load_scene(test::source_path("scenes/cornell-fog.xml"),
                             {{"type", "vpm"}, {"photons_per_pass", "5000"}});
    v.set_resolution(16, 16);
    CHECK(render_test(v, 2, 1, 4).film.pixels == render_test(v, 2, 3, 4).film.pixels);
    v.media[0].sigma_a = RGB{0.01f};
    v.media[0].Le = RGB{1.f};
    try {
        render_test(v, 1);
        FAIL("rendered");
    } catch (const InputError& e) {
        CHECK(std::string(e.what()).find("cornell-fog.xml:" + std::to_string(v.media[0].line) +
                                         ": medium 'fog' emits") != std::string::npos);
        CHECK(std::string(e.what()).find("vpm sends photons from lights only") !=
              std::string::npos);
    }
}
