// Adaptive photon tracing (Hachisuka and Jensen 2011; the photon thesis' 8.1.1 future work):
// the visible-point grid against brute force; adaptive SPPM converging to the same image as
// uniform photons on the diffuse Cornell box; a lower error at equal photons where nearly all
// photons land out of view; images independent of the thread count.
#include <catch2/catch.hpp>
#include <cmath>

#include "engine/core/rng.h"
#include "engine/film/metrics.h"
#include "engine/scene/xml_loader.h"
#include "engine/transport/photon/adaptive_photons.h"
#include "image_checks.h"
#include "test_util.h"

using namespace foton;

namespace {

// A 100 x 100 floor under a light as large; the camera sees a 2 x 2 wall standing on it, lit
// indirectly by the floor: about 1 photon path in 5,000 reaches what the camera sees.
const char* kWideFloorWall = R"(<?xml version="1.0"?>
<scene>
  <lights>
    <area><radiance r="1" g="1" b="1"/><corner x="-50" y="20" z="-50"/>
      <edge1 x="100" y="0" z="0"/><edge2 x="0" y="0" z="100"/></area>
  </lights>
  <objects>
    <quad name="floor"><corner x="-50" y="0" z="-50"/><edge1 x="0" y="0" z="100"/>
      <edge2 x="100" y="0" z="0"/>
      <material type="lambert"><reflectance r="0.5" g="0.5" b="0.5"/></material></quad>
    <quad name="wall"><corner x="-1" y="0" z="0"/><edge1 x="0" y="2" z="0"/><edge2 x="2" y="0" z="0"/>
      <material type="lambert"><reflectance r="0.7" g="0.7" b="0.7"/></material></quad>
  </objects>
  <film width="32" height="32"/>
  <renderer type="sppm" max_depth="4" photons_per_pass="4096"/>
  <camera fov="30"><eye x="0" y="1" z="-5"/><target x="0" y="1" z="0"/></camera>
</scene>)";

}  // namespace

TEST_CASE("adaptive photons: the visible-point grid finds what brute force finds",
          "[photon][adaptive][fast]") {
    std::vector<SppmPixel> pixels(500);
    for (std::size_t i = 0; i < pixels.size(); ++i) {
        SppmPixel& p = pixels[i];
        p.valid = i % 7 != 0;
        p.p = {10.f * rng::uniform(31, 0, i, 0), 10.f * rng::uniform(31, 0, i, 1),
               rng::uniform(31, 0, i, 2)};
        p.radius = 0.05f + 0.3f * rng::uniform(31, 0, i, 3);
    }
    VisiblePointGrid grid;
    grid.build(pixels);
    int seen = 0;
    for (uint64_t q = 0; q < 20000; ++q) {
        const Vec3 x{10.f * rng::uniform(32, 0, q, 0), 10.f * rng::uniform(32, 0, q, 1),
                     2.f * rng::uniform(32, 0, q, 2) - 0.5f};
        bool want = false;
        for (const SppmPixel& p : pixels)
            want |= p.valid && length_squared(x - p.p) < p.radius * p.radius;
        REQUIRE(grid.sees(x) == want);
        seen += want;
    }
    CHECK(seen > 1000);
    CHECK(seen < 18000);
    VisiblePointGrid none;
    none.build({});
    CHECK_FALSE(none.sees({0, 0, 0}));
}

TEST_CASE("adaptive photons: SPPM renders the diffuse Cornell box as with uniform photons",
          "[photon][adaptive][sppm]") {
    TestScene s(load_scene(test::source_path("scenes/cornell-diffuse.xml")));
    s.set_resolution(48, 48);
    s.render.integrator = "sppm";
    const RenderResult uniform = render_test(s, 48);
    s.render.photon.adaptive_photons = true;
    const RenderResult adaptive = render_test(s, 48);
    const ImageError e = compare_images(adaptive.film, uniform.film);
    test::check_means(e.mean_a, e.mean_b, 0.02);
    // The box's walls see a good share of all paths; mutations are accepted near the target.
    const RenderStats& st = adaptive.stats;
    REQUIRE(st.adaptive_uniform > 0);
    const double seen = double(st.adaptive_seen) / double(st.adaptive_uniform);
    const double accepted = double(st.adaptive_accepted) / double(st.adaptive_mutations);
    INFO("seen " << seen << ", accepted " << accepted);
    CHECK(seen > 0.02);
    CHECK(accepted > 0.1);
    CHECK(accepted < 0.4);
    CHECK(uniform.stats.adaptive_uniform == 0);
}

TEST_CASE("adaptive photons: a lower error at equal photons where photons land out of view",
          "[photon][adaptive][sppm]") {
    TestScene ref_scene(parse_scene(kWideFloorWall, "wide.xml", "."));
    ref_scene.render.integrator = "path";
    const Film ref = render_test(ref_scene, 1024, 0, 99).film;
    double err_uniform = 0.0, err_adaptive = 0.0, mean_adaptive = 0.0;
    for (uint64_t seed : {1, 2}) {
        TestScene s(parse_scene(kWideFloorWall, "wide.xml", "."));
        const RenderResult u = render_test(s, 256, 0, seed);
        s.render.photon.adaptive_photons = true;
        const RenderResult a = render_test(s, 256, 0, seed);
        const ImageError eu = compare_images(u.film, ref), ea = compare_images(a.film, ref);
        INFO("seed " << seed << ": uniform rmse " << eu.rmse << " mean " << eu.mean_a.r
                     << ", adaptive rmse " << ea.rmse << " mean " << ea.mean_a.r
                     << ", reference mean " << eu.mean_b.r << ", seen " << a.stats.adaptive_seen
                     << " of " << a.stats.adaptive_uniform);
        CHECK(double(a.stats.adaptive_seen) < 1e-3 * double(a.stats.adaptive_uniform));
        err_uniform += eu.rmse;
        err_adaptive += ea.rmse;
        mean_adaptive += 0.5 * ea.mean_a.r / ea.mean_b.r;
    }
    INFO("rmse uniform " << err_uniform / 2 << ", adaptive " << err_adaptive / 2
                         << ", adaptive mean / reference " << mean_adaptive);
    CHECK(err_adaptive < 0.85 * err_uniform);
    CHECK(mean_adaptive == Approx(1.0).epsilon(0.04));
}

TEST_CASE("adaptive photons: the image does not depend on the thread count",
          "[photon][adaptive][sppm][fast]") {
    TestScene s(parse_scene(kWideFloorWall, "wide.xml", "."));
    s.set_resolution(16, 16);
    s.render.photon.adaptive_photons = true;
    s.render.photon.photons_per_pass = 9000;  // three chunks, the last partly used
    const RenderResult one = render_test(s, 6, 1, 5), two = render_test(s, 6, 2, 5);
    CHECK(compare_images(one.film, two.film).max_abs == 0.0);
    CHECK(one.stats.adaptive_seen == two.stats.adaptive_seen);
}
