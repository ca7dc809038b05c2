// pbrt-v4's path regularisation (Bsdf::regularized, the `regularize` setting of path and
// volpath): which lobes roughen and how much, that a path's first vertex is left alone, that
// the two integrators agree with it on, and that other integrators say they ignore it.
#include <catch2/catch.hpp>
#include <string>

#include "engine/scene/bsdf.h"
#include "engine/scene/pbrt_loader.h"
#include "engine/scene/xml_loader.h"
#include "engine/transport/registry/render.h"
#include "media_util.h"
#include "test_util.h"

using namespace foton;
using test::image_mean;

TEST_CASE("regularize: specular lobes become alpha 0.1, rough ones below 0.3 double",
          "[bsdf][fast]") {
    Bsdf b;
    b.add(Lobe::lambert(RGB{0.5f}));
    b.add(Lobe::mirror(RGB{0.9f}, Fresnel{}));
    b.add(Lobe::dielectric(1.5f, RGB{1.f}, RGB{1.f}));
    const auto ggx = [](float a) { return MicrofacetDistribution::trowbridge_reitz(a, a); };
    b.add(Lobe::microfacet(RGB{1.f}, ggx(0.05f), Fresnel{}));
    b.add(Lobe::microfacet(RGB{1.f}, MicrofacetDistribution::trowbridge_reitz(0.2f, 0.6f),
                           Fresnel{}));
    REQUIRE(b.has_delta());
    const Bsdf r = b.regularized();
    REQUIRE(r.size() == b.size());
    CHECK(!r.has_delta());
    CHECK(r.lobe(0).type == LobeType::Lambert);
    CHECK(r.lobe(1).type == LobeType::Microfacet);
    CHECK(r.lobe(1).dist.alpha == Approx(0.1f));
    CHECK(r.lobe(1).color == b.lobe(1).color);
    CHECK(r.lobe(2).type == LobeType::RoughDielectric);
    CHECK(r.lobe(2).dist.alpha_y == Approx(0.1f));
    CHECK(r.lobe(2).fresnel.ior == 1.5f);
    CHECK(r.lobe(3).dist.alpha == Approx(0.1f));    // 2 x 0.05
    CHECK(r.lobe(4).dist.alpha == Approx(0.3f));    // 2 x 0.2, at most 0.3
    CHECK(r.lobe(4).dist.alpha_y == Approx(0.6f));  // 0.3 and above: as it was
    // A smooth coat's interface roughens too.
    CoatLayer c;
    Bsdf coated;
    coated.add(Lobe::coated_diffuse(RGB{0.5f}, c));
    const Bsdf rc = coated.regularized();
    CHECK(!rc.lobe(0).coat.coat_smooth);
    CHECK(rc.lobe(0).coat.coat.alpha == Approx(0.1f));
}

TEST_CASE("regularize: path and volpath agree, the first vertex is left alone", "[render]") {
    TestScene s = load_scene(test::source_path("scenes/cornell-glass-caustic.xml"));
    s.set_resolution(24, 24);
    const uint32_t spp = 128 * test::effort();
    s.render.integrator = "path";
    const RGB plain = image_mean(render_test(s, spp, 2, 5).film);
    s.render.regularize = true;
    const RGB path = image_mean(render_test(s, spp, 2, 5).film);
    s.render.integrator = "volpath";
    const RGB vol = image_mean(render_test(s, spp, 2, 5).film);
    INFO("path " << plain.r << " " << plain.g << " " << plain.b << "; regularized: path " << path.r
                 << " " << path.g << " " << path.b << ", volpath " << vol.r << " " << vol.g << " "
                 << vol.b);
    CHECK(vol.r == Approx(path.r).epsilon(0.02));
    CHECK(vol.g == Approx(path.g).epsilon(0.02));
    CHECK(vol.b == Approx(path.b).epsilon(0.02));
    // Regularisation blurs the caustic, it does not add or lose much light.
    CHECK(path.g == Approx(plain.g).epsilon(0.05));

    // Seen straight on (the camera's vertex is the path's first), a mirror stays a mirror: the
    // same image, sample for sample.
    const std::string mirror = R"(LookAt 0 0 5  0 0 0  0 1 0
Camera "orthographic"
Film "rgb" "integer xresolution" 8 "integer yresolution" 8
Integrator "path" "integer maxdepth" 1 REG
WorldBegin
LightSource "infinite" "rgb L" [0.5 0.7 0.9]
Material "conductor" "float roughness" 0
Shape "trianglemesh" "point3 P" [-2 -2 0 2 -2 0 2 2 0 -2 2 0] "integer indices" [0 1 2 0 2 3]
)";
    auto with = [&](const std::string& reg) {
        std::string text = mirror;
        text.replace(text.find("REG"), 3, reg);
        return TestScene(parse_pbrt_scene(text, "mirror.pbrt", "."));
    };
    const TestScene on = with("\"bool regularize\" true");
    CHECK(on.render.regularize);
    CHECK(render_test(on, 4, 1, 3).film.pixels == render_test(with(""), 4, 1, 3).film.pixels);
    // Another integrator says it does not regularise.
    TestScene bd(parse_pbrt_scene(
        "Integrator \"bdpt\" \"bool regularize\" true\n" + mirror.substr(mirror.find("WorldBegin")),
        "bd.pbrt", "."));
    bool warned = false;
    for (const std::string& w : bd.warnings) warned |= w.find("regularize ignored") != w.npos;
    CHECK(warned);
}
