// lighting=direct|indirect (the photon thesis' chapter-7 experiments): the two parts add up to
// the whole image, and path tracing, final gathering and direct visualisation agree on each.
#include <catch2/catch.hpp>

#include "engine/accel/intersector.h"
#include "engine/film/metrics.h"
#include "engine/scene/xml_loader.h"
#include "engine/transport/registry/render.h"
#include "test_util.h"

using namespace foton;

namespace {

Film run(TestScene s, const std::string& integrator, Lighting lighting, uint32_t spp,
         const std::string& mode = "final_gather") {
    s.renderer.set("type", integrator, "test", 0);
    if (integrator == "photon") {
        s.renderer.set("mode", mode, "test", 0);
        s.renderer.set("global_photons", "200000", "test", 0);
    }
    s.render = render_settings(s);
    s.render.lighting = lighting;
    s.set_resolution(48, 48);
    const auto acc = make_intersector(s, s.accel);
    RenderOptions opt;
    opt.spp = spp;
    opt.seed = 3;
    return render(s, s.render, *acc, opt).film;
}

RGB mean(const Film& f) {
    RGB s;
    for (const RGB& p : f.pixels) s += p;
    return s * (1.f / float(f.pixels.size()));
}

}  // namespace

TEST_CASE("lighting: direct and indirect add up, and every estimator agrees on each",
          "[integrator][lighting]") {
    const TestScene s = load_scene(test::source_path("scenes/cornell-caustics.xml"));
    // Path tracing: the same random numbers decide the same paths, so the parts are the
    // whole's terms split in two.
    const Film all = run(s, "path", Lighting::All, 16);
    const Film direct = run(s, "path", Lighting::Direct, 16);
    const Film indirect = run(s, "path", Lighting::Indirect, 16);
    const RGB whole = mean(all), parts = mean(direct) + mean(indirect);
    CHECK(parts.g == Approx(whole.g).epsilon(1e-5));
    double worst = 0.0;
    for (std::size_t i = 0; i < all.pixels.size(); ++i)
        worst = std::max(
            worst, double(std::fabs((direct.pixels[i] + indirect.pixels[i]).g - all.pixels[i].g)));
    CHECK(worst < 1e-4);
    const RGB d = mean(direct), ind = mean(indirect);
    // The indirect part is the noisy one (caustic paths): more samples for the comparison.
    const Film indirect_ref = run(s, "path", Lighting::Indirect, 256);
    const RGB ind_ref = mean(indirect_ref);
    // Both parts are there: on this box a quarter of the light is indirect (caustics too).
    CHECK(ind.g > 0.15f * whole.g);
    CHECK(d.g > 0.6f * whole.g);
    // Final gathering's light sample and the direct photons seen directly give the same
    // direct light; the indirect parts agree within the photon estimates' blur.
    // The same camera rays as the path tracer's (same spp and seed), so the directly seen
    // light is the same in both.
    for (const char* mode : {"final_gather", "direct_visualisation"}) {
        const Film pdf = run(s, "photon", Lighting::Direct, 16, mode);
        const Film pif = run(s, "photon", Lighting::Indirect, 16, mode);
        const RGB pd = mean(pdf), pi = mean(pif);
        INFO(mode << ": direct " << pd.g << " vs path " << d.g << "; indirect " << pi.g
                  << " vs path " << ind_ref.g);
        CHECK(pd.g == Approx(d.g).epsilon(0.02));
        CHECK(pi.g == Approx(ind_ref.g).epsilon(0.06));
    }
}

TEST_CASE("lighting: only for path and photon, not with the irradiance cache", "[lighting][fast]") {
    TestScene s = load_scene(test::source_path("scenes/cornell-empty.xml"));
    s.renderer.set("lighting", "direct", "test", 0);
    CHECK(render_settings(s).lighting == Lighting::Direct);
    // Another integrator: a warning at the setting's line, and all light.
    s.renderer.set("type", "light", "test", 7);
    const RenderSettings light = render_settings(s);
    CHECK(light.lighting == Lighting::All);
    REQUIRE(light.warnings.size() == 1);
    CHECK_THAT(light.warnings[0], Catch::Contains("test:0") &&
                                      Catch::Contains("applies to type=\"path\" or \"photon\""));
    s.renderer.set("type", "path", "test", 0);
    s.renderer.set("indirect", "irradiance_cache", "test", 0);
    CHECK_THROWS_WITH(render_settings(s), Catch::Contains("do not combine"));
    s.renderer.set("indirect", "final_gather", "test", 0);
    s.renderer.set("lighting", "some", "test", 0);
    CHECK_THROWS_WITH(render_settings(s), Catch::Contains("lighting"));
}
