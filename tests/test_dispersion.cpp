// Dispersive glass (core/dispersion.h): the Cauchy fit to a catalogue's n_d and Abbe number
// against N-BK7's Sellmeier formula, refraction by the hero wavelength's index, the hero
// carried alone after a dispersive vertex, and spectral volpath through a BK7 slab against
// the same slab without dispersion (the termination must leave the image's mean alone).
#include <catch2/catch.hpp>
#include <cmath>
#include <string>

#include "engine/core/dispersion.h"
#include "engine/core/spectrum.h"
#include "engine/scene/bsdf.h"
#include "engine/scene/pbrt_loader.h"
#include "engine/transport/registry/render.h"
#include "engine/transport/volume/volpath.h"
#include "media_util.h"
#include "test_util.h"

using namespace foton;
using test::image_mean;

namespace {

// SCHOTT's Sellmeier formula for N-BK7 (its catalogue's coefficients, lambda in micrometres).
double bk7_sellmeier(double nm) {
    const double l2 = (nm * 1e-3) * (nm * 1e-3);
    const double n2 = 1.0 + 1.03961212 * l2 / (l2 - 0.00600069867) +
                      0.231792344 * l2 / (l2 - 0.0200179144) + 1.01046945 * l2 / (l2 - 103.560653);
    return std::sqrt(n2);
}

}  // namespace

TEST_CASE("dispersion: the Cauchy fit of n_d and V_d follows N-BK7's Sellmeier formula",
          "[spectral][fast]") {
    Dispersion bk7;
    REQUIRE(named_glass("glass-BK7", bk7));
    CHECK(bk7.disperses());
    // Its own definition: n_d at the d line, the F - C spread (n_d - 1) / V_d.
    CHECK(bk7.ior(587.5618f) == Approx(1.5168f).margin(1e-5));
    CHECK(bk7.ior(486.1327f) - bk7.ior(656.2725f) == Approx(0.5168f / 64.17f).epsilon(1e-3));
    double worst = 0.0;
    for (double nm = 400.0; nm <= 700.0; nm += 5.0)
        worst = std::max(worst, std::fabs(double(bk7.ior(float(nm))) - bk7_sellmeier(nm)));
    INFO("worst difference from the Sellmeier index over 400-700 nm: " << worst);
    CHECK(worst < 1e-3);
    // Every named glass disperses, more the lower its Abbe number.
    Dispersion f5, fk51a;
    REQUIRE(named_glass("glass-F5", f5));
    REQUIRE(named_glass("glass-FK51A", fk51a));
    CHECK(f5.ior(450.f) - f5.ior(650.f) > bk7.ior(450.f) - bk7.ior(650.f));
    CHECK(fk51a.ior(450.f) - fk51a.ior(650.f) < bk7.ior(450.f) - bk7.ior(650.f));
    Dispersion none;
    CHECK(!named_glass("glass-unknown", none));
    CHECK(!none.disperses());
}

TEST_CASE("dispersion: a spectral path refracts by its hero wavelength and carries it alone",
          "[spectral][fast]") {
    Dispersion bk7;
    REQUIRE(named_glass("glass-BK7", bk7));
    Lobe l = Lobe::dielectric(1.5168f, RGB{1.f}, RGB{1.f});
    l.dispersion = bk7;
    // A direction 45 degrees off the normal, refracted at 450 nm and at 650 nm: Snell's law
    // with each wavelength's index, blue bent further.
    const Vec3 wo = normalize(Vec3{1.f, 0.f, 1.f});
    float sin_t[2];
    for (int k = 0; k < 2; ++k) {
        Bsdf b;
        b.add(l);
        REQUIRE(b.disperses());
        Wavelengths w = Wavelengths::sample(0.3f);
        w.lambda[0] = k == 0 ? 450.f : 650.f;
        b.to_wavelengths(w);
        CHECK(b.lobe(0).fresnel.ior == Approx(bk7.ior(w.lambda[0])));
        // uc just below 1 picks transmission (reflection takes the Fresnel share first).
        BsdfSample s;
        REQUIRE(b.sample(wo, 0.999f, {0.5f, 0.5f}, BsdfContext{true, Transport::Radiance}, s));
        REQUIRE(s.wi.z < 0.f);
        sin_t[k] = std::sqrt(s.wi.x * s.wi.x + s.wi.y * s.wi.y);
        CHECK(sin_t[k] == Approx(std::sqrt(0.5f) / bk7.ior(w.lambda[0])).epsilon(1e-4));
    }
    CHECK(sin_t[0] < sin_t[1]);
    // The hero alone from here on, counted three times; once a path.
    Wavelengths w = Wavelengths::sample(0.6f);
    RGB beta{0.5f, 0.25f, 0.125f};
    w.terminate_secondary(beta);
    CHECK(beta == RGB{1.5f, 0.f, 0.f});
    w.terminate_secondary(beta);
    CHECK(beta == RGB{1.5f, 0.f, 0.f});
}

TEST_CASE("dispersion: spectral volpath through a BK7 slab keeps the image's mean",
          "[spectral][render]") {
    // A white emitter seen head-on through a slab: the two faces' transmission (1 - R)^2 with
    // R of n(lambda) differs from the non-dispersive slab's by under 0.1 %, so the means must
    // agree; the hero-only paths are noisier, not darker.
    auto scene = [](const std::string& eta) {
        return "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"orthographic\" \"float screenwindow\" [-1 1 "
               "-1 1]\nFilm \"rgb\" \"integer xresolution\" 8 \"integer yresolution\" 8\n"
               "Integrator \"volpath\" \"integer maxdepth\" 8\nWorldBegin\n"
               "AttributeBegin\nMaterial \"diffuse\" \"rgb reflectance\" [0 0 0]\n"
               "AreaLightSource \"diffuse\" \"rgb L\" [1 1 1]\n"
               "Shape \"trianglemesh\" \"point3 P\" [-3 -3 -2 3 -3 -2 3 3 -2 -3 3 -2] "
               "\"integer indices\" [0 1 2 0 2 3]\nAttributeEnd\n"
               "Material \"dielectric\" " +
               eta +
               "\nShape \"trianglemesh\" \"point3 P\" [-2 -2 0.5 2 -2 0.5 2 2 0.5 -2 2 0.5 "
               "-2 -2 -0.5 2 -2 -0.5 2 2 -0.5 -2 2 -0.5] \"integer indices\" [0 1 2 0 2 3 4 6 5 4 "
               "7 6]\n";
    };
    // Spectral volpath as a user asks for it (pbrt's volpath without media is foton's path
    // tracer); without it, the glass's line warns that it does not disperse.
    const RendererOverrides spectral{{"type", "volpath"}, {"spectral", "true"}};
    const std::string bk7 = scene("\"spectrum eta\" \"glass-BK7\"");
    TestScene glass(parse_pbrt_scene(bk7, "bk7.pbrt", ".", spectral));
    CHECK(integrator_label(glass.render) == "volpath (spectral)");
    CHECK(glass.warnings.empty());
    const Scene rgb = parse_pbrt_scene(bk7, "bk7.pbrt", ".");
    REQUIRE(rgb.warnings.size() == 1);
    CHECK_THAT(rgb.warnings[0], Catch::Contains("bk7.pbrt:11: glass-BK7 disperses only in "
                                                "spectral volpath"));
    TestScene plain(parse_pbrt_scene(scene("\"float eta\" 1.5168"), "plain.pbrt", ".", spectral));
    const uint32_t spp = 256 * test::effort();
    const RGB a = image_mean(render_test(glass, spp, 2, 3).film);
    const RGB b = image_mean(render_test(plain, spp, 2, 3).film);
    INFO("BK7 " << a.r << " " << a.g << " " << a.b << ", n_d only " << b.r << " " << b.g << " "
                << b.b);
    // (1 - R)^2 / (1 - R^2) = 0.919 of the white (R = 0.0422: the faces and the light between
    // them; the emitter is black), without and with dispersion.
    CHECK(b.g == Approx(0.919f).epsilon(0.01));
    CHECK(a.r == Approx(b.r).epsilon(0.01));
    CHECK(a.g == Approx(b.g).epsilon(0.01));
    CHECK(a.b == Approx(b.b).epsilon(0.01));
}
