// Spectral rendering (core/spectrum.h, core/rgb_spectrum.h, volpath's spectral="true"): the
// wavelengths' density, the colorimetry's white, the RGB-to-spectrum fit and its table, and
// spectral volpath against analytic images (a chromatic absorber, a grey furnace), against the
// RGB render where the two must agree, across thread counts, and its errors.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <string>
#include <vector>

#include "engine/core/error.h"
#include "engine/core/rgb_spectrum.h"
#include "engine/core/rng.h"
#include "engine/core/spectrum.h"
#include "engine/scene/pbrt_loader.h"
#include "engine/scene/xml_loader.h"
#include "engine/transport/registry/render.h"
#include "engine/transport/volume/volpath.h"
#include "media_util.h"
#include "test_util.h"

using namespace foton;
using test::image_mean;

namespace {

// The colour a path's values converge to: to_rgb averaged over n stratified wavelength triples,
// the values at each given by `values(w)`.
template <class Values>
RGB colour_over_wavelengths(Values&& values, int n = 20000) {
    double acc[3] = {0.0, 0.0, 0.0};
    for (int i = 0; i < n; ++i) {
        const Wavelengths w = Wavelengths::sample((float(i) + 0.5f) / float(n));
        const RGB c = w.to_rgb(values(w));
        acc[0] += c.r;
        acc[1] += c.g;
        acc[2] += c.b;
    }
    return {float(acc[0] / n), float(acc[1] / n), float(acc[2] / n)};
}

float max_diff(const RGB& a, const RGB& b) {
    return std::max({std::fabs(a.r - b.r), std::fabs(a.g - b.g), std::fabs(a.b - b.b)});
}

// A unit sphere of medium `m` (interface surface) under a white sky, seen orthographically.
std::string sphere_scene(const std::string& medium, const std::string& renderer) {
    return "<scene><film width=\"24\" height=\"24\" size=\"0.1\"/>\n<media>" + medium +
           "</media>\n<lights><environment><color r=\"1\" g=\"1\" b=\"1\"/></environment>"
           "</lights>\n<objects><sphere radius=\"1\" medium_inside=\"m\"><center x=\"0\" y=\"0\" "
           "z=\"0\"/><material type=\"interface\"/></sphere></objects>\n"
           "<renderer type=\"volpath\" max_depth=\"1000\" " +
           renderer +
           "/>\n<camera type=\"orthographic\"><eye x=\"0\" y=\"0\" z=\"5\"/>"
           "<target x=\"0\" y=\"0\" z=\"0\"/></camera></scene>";
}

TestScene parse(const std::string& xml) {
    return TestScene(parse_scene(xml, "spectral.xml", "."));
}

}  // namespace

TEST_CASE("spectral: wavelengths are sampled by their density (chi-square)", "[spectral][fast]") {
    // The density integrates to 1 over [360, 830] nm.
    double integral = 0.0;
    for (int i = 0; i < 47000; ++i) integral += visible_wavelength_pdf(360.f + (i + 0.5f) * 0.01f);
    CHECK(integral * 0.01 == Approx(1.0).epsilon(1e-4));
    CHECK(visible_wavelength_pdf(359.f) == 0.f);
    CHECK(visible_wavelength_pdf(831.f) == 0.f);
    // 47 bins of 10 nm: counts of 200,000 hashed samples against the density's integrals.
    const int bins = 47, n = 200000;
    std::vector<double> count(bins, 0.0);
    for (int i = 0; i < n; ++i) {
        const float l = sample_visible_wavelength(rng::uniform(3, 1, uint64_t(i), 0));
        REQUIRE(l >= 360.f);
        REQUIRE(l <= 830.f);
        count[std::size_t(std::min(bins - 1, int((l - 360.f) / 10.f)))] += 1.0;
    }
    double chi2 = 0.0;
    for (int b = 0; b < bins; ++b) {
        double p = 0.0;
        for (int k = 0; k < 1000; ++k)
            p += visible_wavelength_pdf(360.f + b * 10.f + (k + 0.5f) * 0.01f);
        const double expected = p * 0.01 * n;
        chi2 += (count[std::size_t(b)] - expected) * (count[std::size_t(b)] - expected) / expected;
    }
    // 46 degrees of freedom: the 0.1 % quantile is about 81.
    INFO("chi2 " << chi2);
    CHECK(chi2 < 81.0);
    // A path's other two wavelengths are its first's, a third of the sample space on.
    const Wavelengths w = Wavelengths::sample(0.5f);
    CHECK(w.lambda[1] == sample_visible_wavelength(0.5f + 1.f / 3.f));
    CHECK(w.lambda[2] == sample_visible_wavelength(0.5f + 2.f / 3.f - 1.f));
    CHECK(w.pdf[0] == visible_wavelength_pdf(w.lambda[0]));
}

TEST_CASE("spectral: a white emitter is (1, 1, 1), an emitter's colour is its RGB",
          "[spectral][fast]") {
    const RGB white =
        colour_over_wavelengths([](const Wavelengths& w) { return w.illuminant(RGB{1.f}); });
    INFO(white.r << " " << white.g << " " << white.b);
    CHECK(max_diff(white, RGB{1.f}) < 2e-3f);
    for (const RGB c : {RGB{0.2f, 0.5f, 0.9f}, RGB{3.f, 0.3f, 0.1f}, RGB{0.05f, 0.7f, 0.2f}}) {
        const RGB seen =
            colour_over_wavelengths([&](const Wavelengths& w) { return w.illuminant(c); });
        INFO(c.r << " " << c.g << " " << c.b << " -> " << seen.r << " " << seen.g << " " << seen.b);
        CHECK(max_diff(seen, c) < 0.01f * c.max_component());
    }
}

TEST_CASE("spectral: sigmoid fits reproduce their RGB, the table within a fraction of a per cent",
          "[spectral][fast]") {
    // Greys are constants, exactly.
    for (const float v : {0.f, 0.3f, 0.5f, 1.f}) {
        const SigmoidPolynomial s = RgbSpectrumTable::get().reflectance(RGB{v});
        for (const float l : {360.f, 500.f, 830.f}) CHECK(s(l) == Approx(v).margin(1e-6));
    }
    // Reflectances under the white emitter: the fit exactly, the table's interpolation of fits
    // within its measured error (median 0.08 %, worst 0.9 % at 32^3 nodes).
    std::vector<float> table_err;
    float fit_worst = 0.f;
    for (int i = 0; i < 200; ++i) {
        const RGB c{0.01f + 0.98f * rng::uniform(4, 1, uint64_t(i), 0),
                    0.01f + 0.98f * rng::uniform(4, 1, uint64_t(i), 1),
                    0.01f + 0.98f * rng::uniform(4, 1, uint64_t(i), 2)};
        float residual = 1.f;
        const SigmoidPolynomial fit = fit_sigmoid_polynomial(c, {}, &residual);
        const RGB seen_fit = colour_over_wavelengths(
            [&](const Wavelengths& w) {
                return w.illuminant(RGB{1.f}) *
                       RGB{fit(w.lambda[0]), fit(w.lambda[1]), fit(w.lambda[2])};
            },
            4000);
        fit_worst = std::max(fit_worst, max_diff(seen_fit, c));
        CHECK(residual < 1e-5f);
        const RGB seen_table = colour_over_wavelengths(
            [&](const Wavelengths& w) { return w.illuminant(RGB{1.f}) * w.reflectance(c); }, 4000);
        table_err.push_back(max_diff(seen_table, c));
    }
    std::sort(table_err.begin(), table_err.end());
    INFO("fit worst " << fit_worst << ", table median " << table_err[100] << " worst "
                      << table_err.back());
    CHECK(fit_worst < 2e-3f);  // the 4,000-triple estimate's own error
    CHECK(table_err[100] < 2e-3f);
    CHECK(table_err.back() < 0.012f);
}

TEST_CASE("spectral volpath: a chromatic absorber transmits the integral of exp(-sigma(l) d)",
          "[spectral][render]") {
    const RGB sigma{0.15f, 2.2f, 2.8f};  // the wine of scenes/pbrt/media/media_spheres.pbrt
    const std::string m = "<medium name=\"m\"><sigma_a r=\"0.15\" g=\"2.2\" b=\"2.8\"/></medium>";
    TestScene s = parse(sphere_scene(m, "spectral=\"true\""));
    const RenderResult r = render_test(s, 64 * test::effort(), 2, 3);
    // The reference: each pixel's 4 x 4 chords, each through 400 stratified wavelength
    // triples with the same upsampling the render reads; compared over 4 x 4 pixel blocks
    // (three wavelengths a sample leave colour noise in single pixels).
    const Film& f = r.film;
    std::vector<RGB> ref(f.pixels.size(), RGB{0.f});
    double red_spectral = 0.0, red_rgb = 0.0;
    for (int y = 0; y < f.height; ++y)
        for (int x = 0; x < f.width; ++x) {
            RGB& px = ref[std::size_t(y * f.width + x)];
            for (int j = 0; j < 4; ++j)
                for (int i = 0; i < 4; ++i) {
                    Vec3 o, d;
                    s.camera.generate(float(x) + (i + 0.5f) / 4.f, float(y) + (j + 0.5f) / 4.f,
                                      {0.5f, 0.5f}, o, d);
                    const float r2 = o.x * o.x + o.y * o.y;
                    const float chord = r2 < 1.f ? 2.f * std::sqrt(1.f - r2) : 0.f;
                    px += colour_over_wavelengths(
                              [&](const Wavelengths& w) {
                                  const RGB st = w.unbounded(sigma);
                                  return w.illuminant(RGB{1.f}) * RGB{std::exp(-st.r * chord),
                                                                      std::exp(-st.g * chord),
                                                                      std::exp(-st.b * chord)};
                              },
                              400) *
                          (1.f / 16.f);
                    red_rgb += std::exp(-sigma.r * chord) / 16.f;
                }
            red_spectral += px.r;
        }
    double worst = 0.0;
    for (int by = 0; by < f.height; by += 4)
        for (int bx = 0; bx < f.width; bx += 4) {
            RGB img{0.f}, want{0.f};
            for (int y = by; y < by + 4; ++y)
                for (int x = bx; x < bx + 4; ++x) {
                    img += f.at(x, y) * (1.f / 16.f);
                    want += ref[std::size_t(y * f.width + x)] * (1.f / 16.f);
                }
            worst = std::max(worst, double(max_diff(img, want)));
        }
    const RGB mean = image_mean(f);
    const double n = double(f.width * f.height);
    INFO("worst 4 x 4 block " << worst << "; red: image " << mean.r << ", spectral reference "
                              << red_spectral / n << ", RGB transport " << red_rgb / n);
    // Every block within the wavelengths' noise; the RGB answer is far off.
    CHECK(worst < 0.03);
    CHECK(mean.r == Approx(red_spectral / n).epsilon(0.01));
    CHECK(std::fabs(red_rgb - red_spectral) / n > 0.05);
}

TEST_CASE("spectral volpath: a grey albedo-1 medium conserves energy (furnace)",
          "[spectral][render]") {
    TestScene s = parse(
        sphere_scene("<medium name=\"m\" g=\"0.5\"><sigma_s r=\"3\" g=\"3\" b=\"3\"/></medium>",
                     "spectral=\"true\" transmittance=\"ratio\" free_flight=\"delta\""));
    const RGB mean = image_mean(render_test(s, 32 * test::effort(), 2, 5).film);
    INFO(mean.r << " " << mean.g << " " << mean.b);
    CHECK(mean.r == Approx(1.f).epsilon(0.01));
    CHECK(mean.g == Approx(1.f).epsilon(0.01));
    CHECK(mean.b == Approx(1.f).epsilon(0.01));
}

TEST_CASE(
    "spectral volpath: coloured surfaces as RGB renders them, the same image on any "
    "thread count",
    "[spectral][render]") {
    TestScene s = load_scene(test::source_path("scenes/cornell-diffuse.xml"));
    s.set_resolution(32, 32);
    s.render.integrator = "volpath";
    const uint32_t spp = 128 * test::effort();
    const RGB rgb = image_mean(render_test(s, spp, 2, 4).film);
    VolPathSettings own;
    own.spectral = true;
    s.render.own = own;
    const RenderResult spectral = render_test(s, spp, 2, 4);
    const RGB sp = image_mean(spectral.film);
    INFO("rgb " << rgb.r << " " << rgb.g << " " << rgb.b << ", spectral " << sp.r << " " << sp.g
                << " " << sp.b);
    // Inter-reflections between saturated walls differ between the two by a per cent or two.
    CHECK(sp.r == Approx(rgb.r).epsilon(0.03));
    CHECK(sp.g == Approx(rgb.g).epsilon(0.03));
    CHECK(sp.b == Approx(rgb.b).epsilon(0.03));
    CHECK(render_test(s, 4, 1, 7).film.pixels == render_test(s, 4, 3, 7).film.pixels);
    TestScene fog = load_scene(test::source_path("scenes/cornell-fog.xml"));
    fog.set_resolution(16, 16);
    fog.render.own = own;
    CHECK(render_test(fog, 4, 1, 2).film.pixels == render_test(fog, 4, 3, 2).film.pixels);
}

TEST_CASE("spectral volpath: a conductor given by its reflectance reflects that colour head-on",
          "[spectral][render]") {
    // pbrt-v4's conductor "reflectance": eta 1 and k from r at each wavelength, so the normal
    // reflectance is the colour itself; seen head-on under a white sky, the pixel is r.
    const RGB r{0.95f, 0.64f, 0.54f};
    TestScene s(parse_pbrt_scene(
        "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"orthographic\" \"float screenwindow\" "
        "[-0.5 0.5 -0.5 0.5]\nFilm \"rgb\" \"integer xresolution\" 8 \"integer "
        "yresolution\" 8\nIntegrator \"volpath\" \"integer maxdepth\" 2\nWorldBegin\n"
        "LightSource \"infinite\" \"rgb L\" [1 1 1]\nMaterial \"conductor\" \"rgb "
        "reflectance\" [0.95 0.64 0.54] \"float roughness\" 0\nShape \"trianglemesh\" "
        "\"point3 P\" [-2 -2 0  2 -2 0  2 2 0  -2 2 0] \"integer indices\" [0 1 2 0 2 3]\n",
        "conductor.pbrt", "."));
    VolPathSettings own;
    own.spectral = true;
    s.render.own = own;
    const RGB mean = image_mean(render_test(s, 256, 2, 3).film);
    INFO(mean.r << " " << mean.g << " " << mean.b);
    CHECK(mean.r == Approx(r.r).epsilon(0.01));
    CHECK(mean.g == Approx(r.g).epsilon(0.01));
    CHECK(mean.b == Approx(r.b).epsilon(0.01));
}

TEST_CASE("spectral: only volpath takes it, and not with subsurface materials",
          "[spectral][fast]") {
    const std::string m = "<medium name=\"m\"><sigma_a r=\"1\" g=\"1\" b=\"1\"/></medium>";
    std::string xml = sphere_scene(m, "spectral=\"true\"");
    const std::size_t at = xml.find("type=\"volpath\"");
    xml.replace(at, std::string("type=\"volpath\"").size(), "type=\"path\"");
    // Another integrator warns at the key's line and renders in RGB (pbrt-v4 alike).
    const TestScene path = parse(xml);
    std::string warnings;
    for (const std::string& w : path.render.warnings) warnings += w + "\n";
    INFO(warnings);
    CHECK(warnings.find("spectral.xml:5: setting 'spectral' belongs to type=\"volpath\"") !=
          std::string::npos);
    CHECK(integrator_label(path.render) == "path");
    CHECK(integrator_label(parse(sphere_scene(m, "spectral=\"true\"")).render) ==
          "volpath (spectral)");
    std::string message;
    // A BSSRDF's table is per RGB channel: the render refuses at the material's line.
    TestScene sub = load_scene(test::source_path("scenes/subsurface.xml"));
    sub.set_resolution(8, 8);
    sub.render.integrator = "volpath";
    VolPathSettings own;
    own.spectral = true;
    sub.render.own = own;
    message.clear();
    try {
        render_test(sub, 1, 1, 1);
    } catch (const InputError& e) {
        message = e.what();
    }
    INFO(message);
    CHECK(message.find("subsurface.xml:") != std::string::npos);
    CHECK(message.find("does not render subsurface materials") != std::string::npos);
}
