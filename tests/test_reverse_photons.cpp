// Reverse photon mapping (Havran et al. 2005, the photon-mapping thesis' 6.7): photons find
// the final-gather hits instead of each hit searching the photons. It must give the forward
// search's image, and agree with progressive photon mapping as the thesis' other
// hit-points-first method.
#include <catch2/catch.hpp>

#include "engine/accel/intersector.h"
#include "engine/film/image_io.h"
#include "engine/film/metrics.h"
#include "engine/scene/xml_loader.h"
#include "engine/transport/registry/render.h"
#include "test_util.h"

using namespace foton;

namespace {
TestScene gather_box(const char* name) {
    TestScene s = load_scene(test::source_path(std::string("scenes/") + name));
    s.set_resolution(24, 24);
    s.render.integrator = "photon";
    s.render.photon.mode = PhotonMode::FinalGather;
    s.render.photon.global_photons = 50000;
    s.render.photon.caustic_photons = 20000;
    s.render.photon.gather_rays = 16;
    s.render.photon.irradiance_stride = 0;  // every gather hit takes a full estimate
    return s;
}
}  // namespace

TEST_CASE("reverse photon mapping gives the forward search's final gathering",
          "[photon][reverse]") {
    for (const uint32_t k : {100u, 4096u}) {  // the k nearest, and the whole radius
        TestScene s = gather_box("cornell-diffuse.xml");
        s.render.photon.k = k;
        const RenderResult forward = render_test(s, 2, 0, 3);
        s.render.photon.reverse_lookup = true;
        const RenderResult reverse = render_test(s, 2, 0, 3);
        const ImageError e = compare_images(reverse.film, forward.film);
        INFO("k " << k << ": rmse " << e.rmse << " max " << e.max_abs << " means " << e.mean_a.g
                  << " " << e.mean_b.g);
        // Equal up to the summation order (and photons at the radius' rounding edge).
        CHECK(e.rmse < 1e-4 * e.mean_b.g);
        CHECK(e.mean_a.g == Approx(e.mean_b.g).epsilon(1e-5));
        // And the same for any thread count.
        const RenderResult one = render_test(s, 2, 1, 3);
        CHECK(compare_images(one.film, reverse.film).max_abs == 0.0);
    }
}

TEST_CASE("reverse photon mapping and progressive photon mapping agree", "[photon][reverse]") {
    // Both against pbrt-v4's SPPM reference of the caustics box (box-filtered to 64 x 64, the
    // light's own pixels left out: PPM's fixed visible points alias there).
    TestScene s = gather_box("cornell-caustics.xml");
    s.set_resolution(64, 64);
    s.render.photon.global_photons = 200000;
    s.render.photon.gather_rays = 8;
    s.render.photon.reverse_lookup = true;
    const RenderResult reverse = render_test(s, 2, 0, 5);
    TestScene p = load_scene(test::source_path("scenes/cornell-caustics.xml"));
    p.set_resolution(64, 64);
    p.render.integrator = "ppm";
    p.render.photon.initial_radius = 4.f;
    p.render.photon.photons_per_pass = 65536;
    const RenderResult ppm = render_test(p, 16, 0, 5);
    const Film ref =
        downsample(read_exr(test::shared_path("refs/cornell_caustics_sppm_256it.exr")), 8);
    std::vector<uint8_t> mask(ref.pixels.size());
    for (std::size_t i = 0; i < mask.size(); ++i) mask[i] = ref.pixels[i].max_component() < 1.f;
    const ImageError er = compare_images(reverse.film, ref, &mask),
                     ep = compare_images(ppm.film, ref, &mask);
    INFO("means: reverse " << er.mean_a.r << " " << er.mean_a.g << " " << er.mean_a.b << ", ppm "
                           << ep.mean_a.r << " " << ep.mean_a.g << " " << ep.mean_a.b
                           << ", reference " << er.mean_b.r << " " << er.mean_b.g << " "
                           << er.mean_b.b);
    CHECK(er.mean_a.r == Approx(ep.mean_a.r).epsilon(0.02));
    CHECK(er.mean_a.g == Approx(ep.mean_a.g).epsilon(0.02));
    CHECK(er.mean_a.b == Approx(ep.mean_a.b).epsilon(0.02));
    CHECK(er.mean_a.g == Approx(er.mean_b.g).epsilon(0.02));
}
