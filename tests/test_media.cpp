// Participating media: the Henyey-Greenstein phase function, delta and ratio tracking against
// exp(-sigma_t d), and volumetric path tracing against analytic images (an absorbing sphere,
// an albedo-1 furnace, an infinite emitting medium) and against the path tracer.
#include <catch2/catch.hpp>
#include <cmath>
#include <string>

#include "chi_square.h"
#include "engine/core/error.h"
#include "engine/core/rng.h"
#include "engine/film/metrics.h"
#include "engine/scene/xml_loader.h"
#include "engine/transport/common/medium_tracking.h"
#include "engine/transport/volume/volpath.h"
#include "media_util.h"
#include "test_util.h"

using namespace foton;
using test::image_mean;

namespace {

Medium medium(RGB sigma_a, RGB sigma_s, float g = 0.f) {
    Medium m;
    m.sigma_a = sigma_a;
    m.sigma_s = sigma_s;
    m.g = g;
    return m;
}

// A sphere of radius 1 at the origin bounding medium `inside` (an interface surface), under a
// white sky, seen by an orthographic camera along -z.
std::string sphere_scene(const std::string& medium, const std::string& extra = "",
                         const std::string& renderer = "") {
    return std::string("<scene><film width=\"24\" height=\"24\" size=\"0.1\"/>\n") + "<media>" +
           medium + "</media>\n" +
           "<lights><environment><color r=\"1\" g=\"1\" b=\"1\"/></environment></lights>\n" +
           "<objects><sphere radius=\"1\" medium_inside=\"m\"><center x=\"0\" y=\"0\" z=\"0\"/>" +
           "<material type=\"interface\"/></sphere>" + extra + "</objects>\n" +
           "<renderer type=\"volpath\" max_depth=\"1000\" " + renderer + "/>\n" +
           "<camera type=\"orthographic\"><eye x=\"0\" y=\"0\" z=\"5\"/>"
           "<target x=\"0\" y=\"0\" z=\"0\"/></camera></scene>";
}

TestScene parse(const std::string& xml) {
    return TestScene(parse_scene(xml, "media.xml", "."));
}

}  // namespace

TEST_CASE("Henyey-Greenstein: normalised, sampled by its own density (chi-square)",
          "[media][fast]") {
    int index = 0;
    for (const float g : {-0.7f, 0.f, 0.3f, 0.9f}) {
        const Vec3 wo = normalize(Vec3{0.3f, -0.5f, 0.8f});
        test::ChiSquareSetup setup;
        setup.axis = -wo;  // the forward peak
        setup.samples = 100000;
        ++index;
        const auto r = test::chi_square(
            setup,
            [&](int i, Vec3& wi) {
                const float pdf =
                    sample_henyey_greenstein(wo, g,
                                             {rng::uniform(5, uint64_t(index), uint64_t(i), 0),
                                              rng::uniform(5, uint64_t(index), uint64_t(i), 1)},
                                             wi);
                CHECK(pdf == Approx(henyey_greenstein(dot(wo, wi), g)).epsilon(1e-4));
                return true;
            },
            [&](const Vec3& wi) { return double(henyey_greenstein(dot(wo, wi), g)); });
        INFO("g " << g << ": " << r.summary());
        CHECK(r.p_value > 0.01 / 4);
        CHECK(r.expected_total == Approx(1.0).margin(2e-3));
    }
    // Forward scattering for g > 0: the mean cosine to the continuing direction is g.
    double mean_cos = 0.0;
    const int n = 200000;
    const Vec3 wo{0, 0, 1};
    for (int i = 0; i < n; ++i) {
        Vec3 wi;
        sample_henyey_greenstein(
            wo, 0.6f, {rng::uniform(6, 0, uint64_t(i), 0), rng::uniform(6, 0, uint64_t(i), 1)}, wi);
        mean_cos += dot(wi, -wo);
    }
    CHECK(mean_cos / n == Approx(0.6).margin(5e-3));
}

TEST_CASE("delta tracking: passes with exp(-sigma_t d), scatters by sigma_s exp(-sigma_t t)",
          "[media][fast]") {
    // A chromatic medium: the majorant is the blue channel's, red and green see null collisions.
    const Medium m = medium({0.2f, 0.5f, 1.f}, {0.8f, 0.3f, 0.1f});
    const float d = 1.5f;
    const int n = 400000;
    const int bins = 6;
    RGB pass{0.f}, pass2{0.f};
    std::vector<RGB> scatter(bins, RGB{0.f});
    for (int i = 0; i < n; ++i) {
        test::Draws u{99, 11, uint64_t(i)};
        const FreeFlight f = delta_track(m, d, RGB{1.f}, u);
        if (f.event == FreeFlight::Event::Pass) {
            pass += f.weight;
            pass2 += f.weight * f.weight;
        } else if (f.event == FreeFlight::Event::Scatter) {
            CHECK(f.t < d);
            scatter[std::size_t(std::min(bins - 1, int(f.t / d * bins)))] += f.weight;
        }
    }
    const RGB st = m.sigma_t();
    const float sa[3] = {st.r, st.g, st.b}, ss[3] = {m.sigma_s.r, m.sigma_s.g, m.sigma_s.b};
    const float got[3] = {pass.r / n, pass.g / n, pass.b / n};
    const float sq[3] = {pass2.r / n, pass2.g / n, pass2.b / n};
    for (int c = 0; c < 3; ++c) {
        const float expected = std::exp(-sa[c] * d);
        const float se = std::sqrt(std::max(1e-12f, sq[c] - got[c] * got[c]) / n);
        INFO("channel " << c << ": " << got[c] << " vs " << expected << " (se " << se << ")");
        CHECK(std::fabs(got[c] - expected) < 5.f * se + 1e-4f);
        for (int b = 0; b < bins; ++b) {
            const float t0 = d * b / bins, t1 = d * (b + 1) / bins;
            // The expected weight of scattering in [t0, t1): sigma_s / sigma_t of the
            // probability of a real collision there.
            const float e = ss[c] / sa[c] * (std::exp(-sa[c] * t0) - std::exp(-sa[c] * t1));
            const RGB w = scatter[std::size_t(b)] * (1.f / n);
            const float g = c == 0 ? w.r : c == 1 ? w.g : w.b;
            INFO("bin " << b << ": " << g << " vs " << e);
            CHECK(g == Approx(e).epsilon(0.03).margin(2e-3));
        }
    }
}

TEST_CASE("delta tracking: a grey medium's collision distances (chi-square)", "[media][fast]") {
    const Medium m = medium(RGB{0.f}, RGB{1.3f});
    const float d = 2.f;
    const int n = 100000, bins = 20;
    std::vector<double> observed(bins + 1, 0.0);
    for (int i = 0; i < n; ++i) {
        test::Draws u{99, 12, uint64_t(i)};
        const FreeFlight f = delta_track(m, d, RGB{1.f}, u);
        REQUIRE(f.event != FreeFlight::Event::Absorb);
        // Grey and without absorption: every event weighs exactly 1.
        CHECK(f.weight.r == 1.f);
        observed[f.event == FreeFlight::Event::Pass
                     ? bins
                     : std::size_t(std::min(bins - 1, int(f.t / d * bins)))] += 1.0;
    }
    double chi2 = 0.0;
    for (int b = 0; b <= bins; ++b) {
        const double t0 = d * b / bins, t1 = d * (b + 1) / bins;
        const double p = b == bins ? std::exp(-1.3 * d) : std::exp(-1.3 * t0) - std::exp(-1.3 * t1);
        const double e = p * n;
        chi2 += (observed[std::size_t(b)] - e) * (observed[std::size_t(b)] - e) / e;
    }
    const double p_value = test::gamma_q(0.5 * bins, 0.5 * chi2);
    INFO("chi2 " << chi2 << " p " << p_value);
    CHECK(p_value > 0.01);
}

TEST_CASE("ratio tracking and the emission along a flight are unbiased", "[media][fast]") {
    const Medium m = medium({0.3f, 0.6f, 0.9f}, {0.5f, 0.1f, 0.f});
    const float d = 1.2f;
    const int n = 200000;
    RGB sum{0.f};
    for (int i = 0; i < n; ++i) {
        test::Draws u{99, 13, uint64_t(i)};
        sum += ratio_track(m, d, u);
    }
    const RGB exact = m.transmittance(d);
    CHECK(sum.r / n == Approx(exact.r).epsilon(0.01));
    CHECK(sum.g / n == Approx(exact.g).epsilon(0.01));
    CHECK(sum.b / n == Approx(exact.b).epsilon(0.01));
    test::Draws u{99, 14, 0};
    CHECK(transmittance(m, Vec3{}, Vec3{0, 0, 1}, d, TransmittanceEstimator::Exact, u).g ==
          Approx(std::exp(-0.7f * d)));
    // In an unbounded medium a flight gathers sigma_a Le / sigma_t before its first real event.
    Medium glow = m;
    glow.Le = RGB{1.f, 2.f, 4.f};
    RGB emitted{0.f};
    for (int i = 0; i < n; ++i) {
        test::Draws v{99, 15, uint64_t(i)};
        emitted += delta_track(glow, kInfinity, RGB{1.f}, v).emitted;
    }
    const RGB st = glow.sigma_t();
    CHECK(emitted.r / n == Approx(glow.sigma_a.r * 1.f / st.r).epsilon(0.01));
    CHECK(emitted.g / n == Approx(glow.sigma_a.g * 2.f / st.g).epsilon(0.01));
    CHECK(emitted.b / n == Approx(glow.sigma_a.b * 4.f / st.b).epsilon(0.01));
}

TEST_CASE("volpath: an absorbing sphere under a white sky transmits exp(-sigma_a chord)",
          "[media][render]") {
    const RGB sigma{0.4f, 0.9f, 1.6f};
    TestScene s =
        parse(sphere_scene("<medium name=\"m\"><sigma_a r=\"0.4\" g=\"0.9\" b=\"1.6\"/></medium>"));
    const uint32_t spp = 64 * test::effort();
    const RenderResult r = render_test(s, spp, 2, 3);
    const Film& f = r.film;
    // The pixel's mean over its area, by a 16 x 16 grid of the camera's own rays.
    double worst = 0.0, sum_err = 0.0;
    for (int y = 0; y < f.height; ++y)
        for (int x = 0; x < f.width; ++x) {
            RGB ref{0.f};
            for (int j = 0; j < 16; ++j)
                for (int i = 0; i < 16; ++i) {
                    Vec3 o, d;
                    s.camera.generate(float(x) + (i + 0.5f) / 16.f, float(y) + (j + 0.5f) / 16.f,
                                      {0.5f, 0.5f}, o, d);
                    const float r2 = o.x * o.x + o.y * o.y;
                    const float chord = r2 < 1.f ? 2.f * std::sqrt(1.f - r2) : 0.f;
                    ref += RGB{std::exp(-sigma.r * chord), std::exp(-sigma.g * chord),
                               std::exp(-sigma.b * chord)};
                }
            ref *= 1.f / 256.f;
            const RGB& p = f.at(x, y);
            const double e =
                std::max({std::fabs(p.r - ref.r), std::fabs(p.g - ref.g), std::fabs(p.b - ref.b)});
            worst = std::max(worst, e);
            sum_err += e;
        }
    INFO("worst pixel error " << worst << ", mean " << sum_err / (f.width * f.height));
    // Red and green see null collisions (blue is the majorant): noise of a few per cent at
    // 64 samples, none where the chord is 0.
    CHECK(worst < 0.08);
    CHECK(sum_err / (f.width * f.height) < 0.01);
}

TEST_CASE("volpath: an albedo-1 medium under a white sky conserves energy (furnace)",
          "[media][render]") {
    for (const char* settings : {"transmittance=\"exact\" free_flight=\"analytic\"",
                                 "transmittance=\"ratio\" free_flight=\"delta\""}) {
        INFO(settings);
        TestScene s = parse(
            sphere_scene("<medium name=\"m\" g=\"0.5\"><sigma_s r=\"3\" g=\"3\" b=\"3\"/></medium>",
                         "", std::string(settings) + " mis=\"power\""));
        const RenderResult r = render_test(s, 32 * test::effort(), 2, 5);
        const RGB mean = image_mean(r.film);
        INFO(mean.r << " " << mean.g << " " << mean.b);
        CHECK(mean.r == Approx(1.f).epsilon(0.01));
        CHECK(mean.g == Approx(1.f).epsilon(0.01));
        CHECK(mean.b == Approx(1.f).epsilon(0.01));
    }
}

TEST_CASE("volpath: an unbounded emitting medium has radiance Le everywhere", "[media][render]") {
    // The camera sits in the medium; a far, small sphere only makes the scene non-empty.
    const std::string xml =
        "<scene><film width=\"16\" height=\"16\"/>\n"
        "<media><medium name=\"glow\"><sigma_a r=\"0.5\" g=\"0.5\" b=\"0.5\"/>"
        "<sigma_s r=\"0.5\" g=\"0.2\" b=\"0\"/><emission r=\"1\" g=\"0.5\" "
        "b=\"0.25\"/></medium></media>\n"
        "<objects><sphere radius=\"0.01\"><center x=\"0\" y=\"0\" z=\"-1000\"/>"
        "<material type=\"lambert\"/></sphere></objects>\n"
        "<renderer type=\"volpath\" max_depth=\"200\"/>\n"
        "<camera medium=\"glow\" fov=\"60\"><eye x=\"0\" y=\"0\" z=\"0\"/>"
        "<target x=\"0\" y=\"0\" z=\"-1\"/></camera></scene>";
    TestScene s = parse(xml);
    CHECK(s.camera_medium == 0);
    for (const FreeFlightSampling how : {FreeFlightSampling::Analytic, FreeFlightSampling::Delta}) {
        VolPathSettings own;
        own.free_flight = how;
        s.render.own = own;
        // Delta tracking's chromatic null collisions are noisier (about 0.4 % standard error in
        // red at 256 samples a pixel, over seeds): more samples, a wider margin.
        const bool delta = how == FreeFlightSampling::Delta;
        const RGB mean = image_mean(render_test(s, (delta ? 64 : 16) * test::effort(), 2, 9).film);
        const float tol = delta ? 0.03f : 0.01f;
        INFO("delta " << delta << ": " << mean.r << " " << mean.g << " " << mean.b);
        CHECK(mean.r == Approx(1.f).epsilon(tol));
        CHECK(mean.g == Approx(0.5f).epsilon(tol));
        CHECK(mean.b == Approx(0.25f).epsilon(tol));
    }
}

TEST_CASE("volpath without media renders the path tracer's image", "[media][render]") {
    TestScene s = load_scene(test::source_path("scenes/cornell-diffuse.xml"));
    s.set_resolution(32, 32);
    const uint32_t spp = 128 * test::effort();
    s.render.integrator = "path";
    const RGB path = image_mean(render_test(s, spp, 2, 4).film);
    s.render.integrator = "volpath";
    const RGB vol = image_mean(render_test(s, spp, 2, 4).film);
    INFO("path " << path.r << " " << path.g << " " << path.b << ", volpath " << vol.r << " "
                 << vol.g << " " << vol.b);
    CHECK(vol.r == Approx(path.r).epsilon(0.02));
    CHECK(vol.g == Approx(path.g).epsilon(0.02));
    CHECK(vol.b == Approx(path.b).epsilon(0.02));
}

TEST_CASE("volpath: the same image for any thread count and accelerator", "[media][render]") {
    TestScene s = load_scene(test::source_path("scenes/cornell-fog.xml"));
    s.set_resolution(24, 24);
    auto render_with = [&](AccelType a, int threads) {
        const auto acc = make_intersector(s, a);
        RenderOptions opt;
        opt.spp = 4;
        opt.threads = threads;
        opt.seed = 2;
        return render(s, s.render, *acc, opt).film.pixels;
    };
    const auto one = render_with(AccelType::Bvh, 1);
    CHECK(render_with(AccelType::Bvh, 3) == one);
    CHECK(render_with(AccelType::Grid, 2) == one);
    CHECK(render_with(AccelType::Brute, 2) == one);
}

TEST_CASE("media: bad input names the file and line", "[media][fast]") {
    auto error_of = [](const std::string& xml) -> std::string {
        try {
            parse(xml);
        } catch (const InputError& e) {
            return e.what();
        }
        return "";
    };
    const std::string ok = "<medium name=\"m\"><sigma_a r=\"1\" g=\"1\" b=\"1\"/></medium>";
    CHECK(error_of(sphere_scene(ok)) == "");
    CHECK(error_of(sphere_scene("<medium name=\"m\" g=\"1\"><sigma_s r=\"1\" g=\"1\" "
                                "b=\"1\"/></medium>"))
              .find("media.xml:2: the phase function's g must be in (-1, 1)") != std::string::npos);
    CHECK(error_of(sphere_scene("<medium name=\"m\" type=\"cloud\"/>"))
              .find("unknown medium type 'cloud'") != std::string::npos);
    CHECK(error_of(sphere_scene("<medium name=\"m\"><sigma_s r=\"-1\" g=\"1\" b=\"1\"/></medium>"))
              .find("must not be negative") != std::string::npos);
    CHECK(error_of(sphere_scene(ok + ok)).find("medium 'm' defined twice") != std::string::npos);
    CHECK(error_of(sphere_scene("<medium name=\"m\"><sigma_s r=\"1\" g=\"1\" b=\"1\"/>"
                                "<emission r=\"1\" g=\"1\" b=\"1\"/></medium>"))
              .find("an emitting medium needs absorption") != std::string::npos);
    CHECK(error_of(sphere_scene(ok,
                                "<sphere radius=\"1\" medium_outside=\"fog\"><center x=\"3\" "
                                "y=\"0\" z=\"0\"/><material type=\"lambert\"/></sphere>"))
              .find("unknown medium 'fog' in attribute 'medium_outside' (m)") != std::string::npos);
    // An integrator that does not trace media refuses the scene at the medium's line.
    TestScene s = parse(sphere_scene(ok));
    s.render.integrator = "path";
    try {
        render_test(s, 1);
        FAIL("rendered");
    } catch (const InputError& e) {
        CHECK(std::string(e.what()) ==
              "media.xml:2: the scene has participating media, which type=\"path\" does not "
              "trace: use type=\"light\", \"bdpt\", \"vcm\", \"volpath\" or \"vpm\"");
    }
}
