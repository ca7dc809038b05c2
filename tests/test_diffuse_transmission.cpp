// Diffuse transmission (a Lambert lobe of transmittance T on the side away from the viewer,
// beside a Lambert reflection: pbrt-v4's diffusetransmission): sampling against its pdf on
// both sides (chi-square), reciprocity, the directional albedo R + T, the XML and pbrt
// readers, and a lamp shade's light reaching the floor only through it, rendered alike by the
// path tracer, the light tracer, bdpt and photon mapping.
#include <catch2/catch.hpp>

#include "chi_square.h"
#include "engine/core/rng.h"
#include "engine/film/metrics.h"
#include "engine/scene/bsdf.h"
#include "engine/scene/pbrt_loader.h"
#include "engine/scene/xml_loader.h"
#include "test_util.h"

using namespace foton;

namespace {

Bsdf paper() {
    Bsdf b;
    b.add(Lobe::lambert(RGB{0.3f, 0.25f, 0.2f}));
    b.add(Lobe::lambert_transmission(RGB{0.5f, 0.45f, 0.3f}));
    return b;
}

Vec3 direction(float theta_deg, float phi) {
    const float t = theta_deg * kPi / 180.f;
    return {std::sin(t) * std::cos(phi), std::sin(t) * std::sin(phi), std::cos(t)};
}

// A lamp shade: a translucent panel under a downward area light, over a floor that sees the
// light only through the panel (and the panel's underside from the camera).
const char* kShade = R"(<scene><lights/><objects>
    <quad><corner x="-3" y="0" z="-3"/><edge1 x="0" y="0" z="6"/><edge2 x="6" y="0" z="0"/>
      <material type="lambert"><reflectance r="0.7" g="0.7" b="0.7"/></material></quad>
    <quad><corner x="-1.5" y="2" z="-1.5"/><edge1 x="3" y="0" z="0"/><edge2 x="0" y="0" z="3"/>
      <material type="diffuse_transmission"><reflectance r="0.3" g="0.25" b="0.2"/>
      <transmittance r="0.55" g="0.5" b="0.35"/></material></quad>
    <quad><corner x="-0.5" y="3" z="-0.5"/><edge1 x="1" y="0" z="0"/><edge2 x="0" y="0" z="1"/>
      <material type="lambert"><reflectance r="0" g="0" b="0"/><emission r="20" g="20" b="20"/></material></quad>
  </objects><film width="40" height="30"/><renderer type="path" max_depth="6"/>
  <camera fov="50"><eye x="0" y="1.2" z="-6"/><target x="0" y="0.8" z="0"/></camera></scene>)";

}  // namespace

TEST_CASE("diffuse transmission: sampling, reciprocity and albedo", "[bsdf][fast]") {
    const Bsdf b = paper();
    REQUIRE(b.transmits_non_delta());
    int index = 0;
    for (const float theta : {0.f, 50.f, 85.f}) {
        for (const bool flip : {false, true}) {
            ++index;
            Vec3 wo = direction(theta, 0.3f);
            if (flip) wo.z = -wo.z;
            const BsdfContext ctx{!flip, Transport::Radiance};
            test::ChiSquareSetup setup;
            setup.samples = 100000;
            const auto r = test::chi_square(
                setup,
                [&](int i, Vec3& wi) {
                    BsdfSample s;
                    if (!b.sample(wo, rng::uniform(15, uint64_t(index), uint64_t(i), 0),
                                  {rng::uniform(15, uint64_t(index), uint64_t(i), 1),
                                   rng::uniform(15, uint64_t(index), uint64_t(i), 2)},
                                  ctx, s))
                        return false;
                    wi = s.wi;
                    return true;
                },
                [&](const Vec3& wi) { return double(b.pdf(wo, wi, ctx)); });
            INFO(theta << " deg, flip " << flip << ": " << r.summary());
            CHECK(r.p_value > 0.01 / 6);
            CHECK(r.expected_total == Approx(r.observed_total).margin(0.01));
            // Directional albedo: R + T exactly in expectation.
            double sum = 0.0;
            const int n = 50000;
            for (int i = 0; i < n; ++i) {
                BsdfSample s;
                if (b.sample(
                        wo, rng::uniform(16, 0, uint64_t(i), 0),
                        {rng::uniform(16, 0, uint64_t(i), 1), rng::uniform(16, 0, uint64_t(i), 2)},
                        ctx, s))
                    sum += double(s.f.g) * std::fabs(s.wi.z) / s.pdf;
            }
            CHECK(sum / n == Approx(0.25 + 0.45).epsilon(0.01));
        }
    }
    // Reciprocity, and nothing where the lobes do not reach.
    const Vec3 a = direction(30.f, 0.5f), c = direction(140.f, 2.f);
    CHECK(b.f(a, c, {}).g == Approx(b.f(c, a, {}).g));
    CHECK(b.f(a, c, {}).g == Approx(0.45f / kPi));
    CHECK(b.f(a, direction(60.f, 1.f), {}).g == Approx(0.25f / kPi));
}

TEST_CASE("diffuse transmission: the XML and pbrt readers", "[bsdf][fast]") {
    const TestScene s = parse_scene(kShade, "shade.xml", ".");
    const Bsdf& b = s.materials[s.objects[1].material].bsdf;
    REQUIRE(b.size() == 2);
    CHECK(b.lobe(1).type == LobeType::LambertTransmission);
    CHECK(b.lobe(1).color.g == Approx(0.5f));
    const std::string too_bright =
        std::string(kShade).replace(std::string(kShade).find("r=\"0.55\""), 8, "r=\"0.75\"");
    CHECK_THROWS_WITH(parse_scene(too_bright, "shade.xml", "."),
                      Catch::Contains("shade.xml:5") && Catch::Contains("at most 1"));
    const Scene p = parse_pbrt_scene(
        "WorldBegin\nMaterial \"diffusetransmission\" \"rgb transmittance\" [0.6 0.5 0.4] "
        "\"float scale\" 0.5\nShape \"sphere\" \"float radius\" 1\n",
        "t.pbrt", ".");
    const Bsdf& pb = p.materials.back().bsdf;
    REQUIRE(pb.size() == 2);
    CHECK(pb.lobe(0).color.g == Approx(0.125f));  // the default reflectance 0.25, scaled
    CHECK(pb.lobe(1).color.r == Approx(0.3f));
}

TEST_CASE("diffuse transmission: a lamp shade renders alike in every integrator", "[integrators]") {
    TestScene scene = parse_scene(kShade, "shade.xml", ".");
    const uint32_t e = test::effort();
    const Film ref = render_test(scene, 1024 * e, 0, 31).film;
    const std::vector<uint8_t> mask =
        grow_exclusion(luminance_mask(ref, 2.f), ref.width, ref.height, 1);
    for (const auto& [type, spp] :
         {std::pair{"light", 512u}, std::pair{"bdpt", 64u}, std::pair{"photon", 8u}}) {
        INFO(type);
        TestScene s = scene;
        s.render.integrator = type;
        const Film img = render_test(s, spp * e, 0, 32).film;
        const ImageError err = compare_images(img, ref, &mask);
        INFO("means " << err.mean_a.g << " vs " << err.mean_b.g);
        CHECK(err.mean_a.r == Approx(err.mean_b.r).epsilon(0.025));
        CHECK(err.mean_a.g == Approx(err.mean_b.g).epsilon(0.025));
        CHECK(err.mean_a.b == Approx(err.mean_b.b).epsilon(0.025));
    }
}
