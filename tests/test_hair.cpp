// The hair BSDF (Chiang et al. 2016, pbrt-v4's `hair`): without absorption it conserves energy
// over the sphere (white furnace, uniform directions) and its sampler's weight f |cos| / pdf is
// 1 without scale tilt; the sampler matches its pdf (chi-square) and the pdf integrates to one;
// absorption darkens it by channel; pbrt's parameters (sigma_a, reflectance, melanin) map as
// pbrt-v4's and bad ones fail at their line; light paths and bdpt, through the fibre's
// adjoint, render separated fibres as the path tracer does.
#include <catch2/catch.hpp>
#include <cmath>

#include "chi_square.h"
#include "engine/core/rng.h"
#include "engine/core/warp.h"
#include "engine/film/metrics.h"
#include "engine/scene/bsdf.h"
#include "engine/scene/pbrt_loader.h"
#include "image_checks.h"
#include "test_util.h"

using namespace foton;

namespace {

Vec3 sphere_dir(float u0, float u1) {
    const float z = 1.f - 2.f * u0, r = std::sqrt(std::max(0.f, 1.f - z * z));
    return {r * std::cos(2.f * kPi * u1), r * std::sin(2.f * kPi * u1), z};
}

Lobe fibre(float h, const RGB& sigma_a, float beta_m, float beta_n, float alpha) {
    HairFiber f;
    f.h = h;
    f.sigma_a = sigma_a;
    f.beta_m = beta_m;
    f.beta_n = beta_n;
    f.alpha_degrees = alpha;
    return Lobe::hair_fiber(f);
}

}  // namespace

TEST_CASE("hair: without absorption the fibre scatters all the light it receives",
          "[hair][bsdf][fast]") {
    const int n = 60000;
    for (float beta_m = 0.1f; beta_m < 1.f; beta_m += 0.2f)
        for (float beta_n = 0.1f; beta_n < 1.f; beta_n += 0.2f) {
            const uint64_t k = uint64_t(beta_m * 100.f) * 1000 + uint64_t(beta_n * 100.f);
            const Vec3 wo = sphere_dir(rng::uniform(21, k, 0, 0), rng::uniform(21, k, 0, 1));
            // One-sample MIS of uniform directions and the fibre's own sampler (its pdf is
            // checked below): the lobes at beta_n 0.1 are too sharp for uniform directions
            // alone at this count.
            double sum = 0.0;
            for (int i = 0; i < n; ++i) {
                const float h = -1.f + 2.f * rng::uniform(22, k, uint64_t(i), 0);
                const Lobe l = fibre(h, RGB{0.f}, beta_m, beta_n, 0.f);
                const float u1 = rng::uniform(22, k, uint64_t(i), 1),
                            u2 = rng::uniform(22, k, uint64_t(i), 2);
                Vec3 wi;
                if (i % 2 == 0) {
                    wi = sphere_dir(u1, u2);
                } else {
                    BsdfSample bs;
                    if (!hair_sample(l, wo, rng::uniform(22, k, uint64_t(i), 3), {u1, u2}, bs))
                        continue;
                    wi = bs.wi;
                }
                const double pdf = 0.5 / (4.0 * kPi) + 0.5 * double(hair_pdf(l, wo, wi));
                sum += double(hair_f(l, wo, wi).g) * std::fabs(wi.z) / pdf;
            }
            const double albedo = sum / n;
            INFO("beta_m " << beta_m << " beta_n " << beta_n << ": " << albedo);
            CHECK(albedo > 0.95);
            CHECK(albedo < 1.05);
        }
}

TEST_CASE("hair: the sampler's weight is 1 without absorption or tilt", "[hair][bsdf][fast]") {
    int checked = 0;
    for (float beta_m = 0.1f; beta_m < 1.f; beta_m += 0.2f)
        for (float beta_n = 0.4f; beta_n < 1.f; beta_n += 0.2f)
            for (uint64_t i = 0; i < 3000; ++i) {
                const uint64_t k = uint64_t(beta_m * 100.f) * 1000 + uint64_t(beta_n * 100.f);
                const Lobe l =
                    fibre(-1.f + 2.f * rng::uniform(23, k, i, 0), RGB{0.f}, beta_m, beta_n, 0.f);
                const Vec3 wo = sphere_dir(rng::uniform(23, k, i, 1), rng::uniform(23, k, i, 2));
                BsdfSample s;
                if (!hair_sample(l, wo, rng::uniform(23, k, i, 3),
                                 {rng::uniform(23, k, i, 4), rng::uniform(23, k, i, 5)}, s))
                    continue;
                // The sample says the side it went to: the integrators drop a "transmission"
                // that stays on wo's side (every reflection was lost so at first).
                CHECK((s.flags & kReflection) == (s.wi.z * wo.z > 0.f ? kReflection : 0));
                CHECK((s.flags & kTransmission) == (s.wi.z * wo.z < 0.f ? kTransmission : 0));
                const float w = s.f.g * std::fabs(s.wi.z) / s.pdf;
                INFO("beta_m " << beta_m << " beta_n " << beta_n << " sample " << i);
                REQUIRE(w == Approx(1.f).margin(2e-3));
                ++checked;
            }
    CHECK(checked > 40000);
}

TEST_CASE("hair: sampling follows the pdf, which integrates to one", "[hair][bsdf][fast]") {
    int index = 0;
    for (const float h : {-0.7f, 0.f, 0.5f})
        for (const float theta_o : {10.f, 60.f}) {
            const Lobe l = fibre(h, RGB{0.3f, 0.8f, 1.6f}, 0.3f, 0.3f, 2.f);
            const float t = theta_o * kPi / 180.f;
            // x along the fibre: theta is the angle from the normal plane.
            const Vec3 wo{std::sin(t), std::cos(t) * std::cos(1.f), std::cos(t) * std::sin(1.f)};
            test::ChiSquareSetup setup;
            setup.axis = {1.f, 0.f, 0.f};  // theta bins resolve the longitudinal lobes
            setup.theta_res = 40;
            setup.phi_res = 40;
            setup.samples = 150000;
            const int idx = index++;
            const auto r = test::chi_square(
                setup,
                [&](int i, Vec3& wi) {
                    BsdfSample s;
                    if (!hair_sample(l, wo, rng::uniform(24, uint64_t(idx), uint64_t(i), 0),
                                     {rng::uniform(24, uint64_t(idx), uint64_t(i), 1),
                                      rng::uniform(24, uint64_t(idx), uint64_t(i), 2)},
                                     s))
                        return false;
                    wi = s.wi;
                    return true;
                },
                [&](const Vec3& wi) { return double(hair_pdf(l, wo, wi)); });
            INFO("h " << h << " theta_o " << theta_o << ": " << r.summary());
            CHECK(r.p_value > 0.01 / 6);
            CHECK(r.expected_total == Approx(1.0).margin(0.01));
            CHECK(r.observed_total == Approx(1.0).margin(0.001));
        }
    // Absorption darkens the channel it is largest in, through the fibre (TT) most.
    const Lobe dark = fibre(0.2f, RGB{0.2f, 0.6f, 1.5f}, 0.3f, 0.3f, 0.f);
    const Vec3 a = normalize(Vec3{0.3f, 0.5f, 0.6f}), b = normalize(Vec3{-0.2f, -0.7f, -0.4f});
    const RGB through = hair_f(dark, a, b);
    CHECK(through.r > through.g);
    CHECK(through.g > through.b);
}

TEST_CASE("hair: pbrt-v4's hair parameters, and bad ones at their line", "[hair][pbrt][fast]") {
    auto lobe_of = [](const std::string& material) {
        const Scene s = parse_pbrt_scene("WorldBegin\nMaterial \"hair\" " + material +
                                             "\nShape \"curve\" \"point3 P\" [0 0 0  1 0 0  2 0 0  "
                                             "3 0 0] \"float width\" [0.1]\n",
                                         "h.pbrt", ".");
        return s.materials[s.objects[0].material].bsdf.lobe(0);
    };
    // Default: eumelanin 1.3.
    const Lobe d = lobe_of("");
    REQUIRE(d.type == LobeType::Hair);
    CHECK(d.hair.sigma_a.r == Approx(1.3f * 0.419f));
    CHECK(d.hair.sigma_a.b == Approx(1.3f * 1.37f));
    CHECK(d.hair.eta == Approx(1.55f));
    const Lobe m = lobe_of("\"float pheomelanin\" [2] \"float beta_m\" [0.2] \"float alpha\" [3]");
    CHECK(m.hair.sigma_a.g == Approx(2.f * 0.4f));
    CHECK(m.hair.beta_m == Approx(0.2f));
    CHECK(m.hair.alpha_degrees == Approx(3.f));
    const Lobe s = lobe_of("\"rgb sigma_a\" [0.1 0.2 0.3]");
    CHECK(s.hair.sigma_a.b == Approx(0.3f));
    // Reflectance: Chiang et al.'s inversion (for beta_n 0.3: (ln c / 5.4684)^2).
    const Lobe r = lobe_of("\"rgb reflectance\" [0.5 0.5 0.5]");
    const float denom = 5.969f - 0.215f * 0.3f + 2.532f * 0.09f - 10.73f * 0.027f +
                        5.574f * 0.0081f + 0.245f * 0.00243f;
    CHECK(r.hair.sigma_a.g == Approx(std::pow(std::log(0.5f) / denom, 2.f)).epsilon(1e-4));
    // "color" is pbrt-v4's other name for it (pbrt-v4-scenes' bunny-fur).
    CHECK(lobe_of("\"rgb color\" [0.5 0.5 0.5]").hair.sigma_a.g == r.hair.sigma_a.g);
    CHECK_THROWS_WITH(lobe_of("\"float beta_n\" [1.5]"),
                      Catch::Contains("h.pbrt:2") && Catch::Contains("beta_n in [0, 1]"));
    CHECK_THROWS_WITH(lobe_of("\"rgb sigma_a\" [-1 0 0]"),
                      Catch::Contains("h.pbrt:2") && Catch::Contains("sigma_a"));
}

TEST_CASE("hair: light paths and bdpt converge to the path tracer on separated fibres",
          "[hair][integrators]") {
    // Five wavy fibres over three widths apart before a grey wall, lit from above and in front, up
    // to 8 bounces. Light paths meet a flat curve's ribbon facing the light, camera paths the
    // one facing the camera; the fibre's adjoint (hair_adjoint_f) makes the two agree. Where
    // fibres touch or overlap they cannot (docs/results.md: a neighbour shades the ribbon a
    // light ray meets otherwise than the one a camera ray meets), so they stand apart here.
    // Measured at effort 1 (red mean's error): light +0.5 %, bdpt -0.2 %; importance through
    // the forward fibre f(wo, wi) (pbrt-v4's choice) +5.2 %, through the adjoint without its
    // cosine rescaled to the fibre's -3.4 %.
    std::string text =
        "LookAt 0 0.2 -4   0 0 0   0 1 0\nCamera \"perspective\" \"float fov\" [ 20 ]\n"
        "Film \"rgb\" \"integer xresolution\" [ 32 ] \"integer yresolution\" [ 24 ]\n"
        "Integrator \"path\" \"integer maxdepth\" [ 8 ]\nWorldBegin\nAttributeBegin\n"
        "AreaLightSource \"diffuse\" \"rgb L\" [ 8 8 8 ]\n"
        "Shape \"trianglemesh\" \"point3 P\" [ -1 3 -2.5  1 3 -2.5  1 3 -1  -1 3 -1 ] "
        "\"integer indices\" [ 0 1 2  0 2 3 ]\nAttributeEnd\n"
        "Material \"diffuse\" \"rgb reflectance\" [ 0.5 0.5 0.5 ]\n"
        "Shape \"trianglemesh\" \"point3 P\" [ -3 -3 0.3  3 -3 0.3  3 3 0.3  -3 3 0.3 ] "
        "\"integer indices\" [ 0 1 2  0 2 3 ]\n"
        "Material \"hair\" \"rgb sigma_a\" [ 0.2 0.4 0.8 ]\n";
    for (int i = 0; i < 5; ++i) {
        const float x = -0.4f + 0.2f * float(i), dz = i % 2 ? 0.1f : 0.f;
        text += "Shape \"curve\" \"string type\" \"flat\" \"float width\" 0.06 \"point3 P\" [ " +
                std::to_string(x) + " -0.8 " + std::to_string(dz) + "  " + std::to_string(x) +
                " -0.3 0.05  " + std::to_string(x) + " 0.3 " + std::to_string(dz - 0.05f) + "  " +
                std::to_string(x) + " 0.8 0 ]\n";
    }
    const TestScene scene(parse_pbrt_scene(text, "fibres.pbrt", "."));
    const uint32_t e = test::effort();
    const Film ref = render_test(scene, 1024 * e, 0, 41).film;
    struct Case {
        const char* integrator;
        uint32_t spp;
        double mean;
    };
    for (const Case& c : {Case{"light", 16384, 0.025}, Case{"bdpt", 256, 0.02}}) {
        INFO(c.integrator);
        TestScene s = scene;
        s.render.integrator = c.integrator;
        const Film img = render_test(s, c.spp * e, 0, 42).film;
        const ImageError err = compare_images(img, ref);
        test::check_means(err.mean_a, err.mean_b, c.mean);
    }
}
