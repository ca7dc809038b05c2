// Visual importance (the photon-mapping thesis' 6.7): importons decide where photons are
// stored. Measured on a scene whose lit geometry is almost all out of view: a 100 x 100 floor
// under a light as large, of which the camera sees a few square units.
#include <catch2/catch.hpp>
#include <cmath>

#include "engine/accel/intersector.h"
#include "engine/film/metrics.h"
#include "engine/scene/xml_loader.h"
#include "engine/transport/common/direct_control_variate.h"
#include "engine/transport/photon/importon_map.h"
#include "engine/transport/registry/render.h"
#include "test_util.h"

using namespace foton;

namespace {

const char* kWideFloor = R"(<?xml version="1.0"?>
<scene>
  <lights>
    <area><radiance r="1" g="1" b="1"/><corner x="-50" y="20" z="-50"/>
      <edge1 x="100" y="0" z="0"/><edge2 x="0" y="0" z="100"/></area>
  </lights>
  <objects>
    <quad name="floor"><corner x="-50" y="0" z="-50"/><edge1 x="0" y="0" z="100"/>
      <edge2 x="100" y="0" z="0"/>
      <material type="lambert"><reflectance r="0.5" g="0.5" b="0.5"/></material></quad>
  </objects>
  <film width="24" height="24"/>
  <renderer type="photon" spp="4" mode="direct_visualisation" caustic_photons="0"
            k="4096" max_radius="0.5"/>
  <camera fov="30"><eye x="0" y="3" z="-6"/><target x="0" y="0" z="0"/></camera>
</scene>)";

// The floor's exact radiance at each pixel centre: rho / pi x Le x the light's cosine
// integral (Lambert's polygon formula; the floor sees nothing else).
Film exact_floor(const Scene& s) {
    Film f(s.film.width, s.film.height);
    const Vec3 light[4] = {{-50, 20, -50}, {50, 20, -50}, {50, 20, 50}, {-50, 20, 50}};
    for (int y = 0; y < f.height; ++y)
        for (int x = 0; x < f.width; ++x) {
            Vec3 o, d;
            s.camera.generate(float(x) + 0.5f, float(y) + 0.5f, o, d);
            const Vec3 p = o + d * (-o.y / d.y);
            const float e = polygon_cosine_integral(light, 4, p, {0, 1, 0});
            f.at(x, y) = RGB{0.5f * kInvPi * e};
        }
    return f;
}

}  // namespace

TEST_CASE("importons put the stored photons where the camera looks", "[photon][importons]") {
    TestScene s(parse_scene(kWideFloor, "wide-floor.xml", test::source_path("scenes")));
    const Film exact = exact_floor(s);
    auto run = [&](uint64_t emitted, uint64_t importons, int threads) {
        TestScene t = s;
        t.render.photon.global_photons = emitted;
        t.render.photon.importons = importons;
        return render_test(t, 4, threads, 1);
    };
    const RenderResult plain = run(20000, 0, 0);
    const RenderResult guided = run(200000, 100000, 0);
    const ImageError ep = compare_images(plain.film, exact),
                     eg = compare_images(guided.film, exact);
    INFO("stored: plain " << plain.stats.photons_global << ", importons "
                          << guided.stats.photons_global << "; RMSE " << ep.rmse << " vs "
                          << eg.rmse << "; means " << ep.mean_a.g << ", " << eg.mean_a.g
                          << ", exact " << ep.mean_b.g);
    // Fewer photons in the map, and less error: the map's photons are where they are read.
    CHECK(guided.stats.photons_global < plain.stats.photons_global);
    CHECK(eg.rmse < 0.5 * ep.rmse);
    // The weights 1 / q keep the estimate unbiased: the mean stays with the exact one.
    CHECK(eg.mean_a.g == Approx(ep.mean_b.g).epsilon(0.03));
    // The same map and image for any thread count.
    const RenderResult one = run(200000, 100000, 1);
    CHECK(one.stats.photons_global == guided.stats.photons_global);
    CHECK(compare_images(one.film, guided.film).max_abs == 0.0);
}

TEST_CASE("the importon map keeps every photon in view and few far away", "[photon][importons]") {
    const Scene s = parse_scene(kWideFloor, "wide-floor.xml", test::source_path("scenes"));
    const auto accel = make_intersector(s, AccelType::Bvh);
    ImportonMap map;
    ImportonSettings is;
    is.count = 50000;
    is.min_probability = 0.05f;
    map.build(s, *accel, is, 7);
    CHECK(map.recorded() == 50000);  // every importon meets the floor
    // The floor in the middle of the view, and a corner of the floor no camera ray reaches.
    CHECK(map.store_probability({0.f, 0.f, 0.f}) == 1.f);
    CHECK(map.store_probability({-45.f, 0.f, 45.f}) == Approx(0.05f));
    CHECK(map.full_fraction() < 0.05f);
    ImportonMap none;
    CHECK(none.empty());
    CHECK(none.store_probability({0.f, 0.f, 0.f}) == 1.f);
}
