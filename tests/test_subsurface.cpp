// Subsurface scattering: the Catmull-Rom splines the profiles are read through, the photon
// beam diffusion table, the BSSRDF's probe sampling against its own density, and the whole
// chain in volpath against the closed form of a semi-infinite slab under a white sky.
#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "engine/core/catmull_rom.h"
#include "engine/core/error.h"
#include "engine/core/rng.h"
#include "engine/scene/pbrt_loader.h"
#include "engine/scene/subsurface/tabulated_bssrdf.h"
#include "engine/scene/xml_loader.h"
#include "kernels/fresnel.h"
#include "test_util.h"

using namespace foton;

namespace {

// The spline through `values` at x, by its weights.
float spline_at(const std::vector<float>& nodes, const std::vector<float>& values, float x) {
    int offset = 0;
    float w[4];
    if (!catmull_rom_weights(nodes, x, offset, w)) return 0.f;
    float s = 0.f;
    for (int j = 0; j < 4; ++j)
        if (w[j] != 0.f) s += w[j] * values[std::size_t(offset + j)];
    return s;
}

const std::vector<float> kNodes = {0.f, 0.1f, 0.25f, 0.3f, 0.6f, 0.7f, 1.f};

}  // namespace

TEST_CASE("subsurface: Catmull-Rom splines reproduce lines, integrate and invert them",
          "[subsurface][fast]") {
    std::vector<float> line, cdf(kNodes.size());
    for (const float x : kNodes) line.push_back(2.f * x + 1.f);
    for (float x = 0.f; x <= 1.f; x += 0.037f)
        CHECK(spline_at(kNodes, line, x) == Approx(2.f * x + 1.f));
    int offset = 0;
    float w[4];
    CHECK_FALSE(catmull_rom_weights(kNodes, 1.01f, offset, w));
    // The integral of 2x + 1 over [0, 1] is 2; up to each node x^2 + x.
    CHECK(integrate_catmull_rom(kNodes, line, cdf) == Approx(2.f));
    for (std::size_t i = 0; i < kNodes.size(); ++i)
        CHECK(cdf[i] == Approx(kNodes[i] * kNodes[i] + kNodes[i]).margin(1e-6));
    for (const float y : {1.1f, 1.5f, 2.2f, 2.9f})
        CHECK(invert_catmull_rom(kNodes, line, y) == Approx((y - 1.f) / 2.f));
}

TEST_CASE("subsurface: 2D Catmull-Rom sampling inverts the interpolated profile's integral",
          "[subsurface][fast]") {
    // Two rows (alpha 0 and 1) of different profiles; at alpha 0.3 the profile is their blend.
    const std::vector<float> alphas = {0.f, 1.f};
    std::vector<float> values, cdf(2 * kNodes.size());
    for (const float x : kNodes) values.push_back(1.f + x);
    for (const float x : kNodes) values.push_back(std::exp(-3.f * x));
    integrate_catmull_rom(kNodes, std::span<const float>(values.data(), kNodes.size()),
                          std::span<float>(cdf.data(), kNodes.size()));
    integrate_catmull_rom(kNodes,
                          std::span<const float>(values.data() + kNodes.size(), kNodes.size()),
                          std::span<float>(cdf.data() + kNodes.size(), kNodes.size()));
    const float alpha = 0.3f;
    // The blend's integral up to x by a fine midpoint rule over the weights' spline.
    std::vector<float> row(kNodes.size());
    for (std::size_t i = 0; i < kNodes.size(); ++i)
        row[i] = 0.7f * values[i] + 0.3f * values[kNodes.size() + i];
    auto integral = [&](float x) {
        const int n = 4000;
        double s = 0.0;
        for (int k = 0; k < n; ++k) s += spline_at(kNodes, row, (k + 0.5f) / n * x);
        return s * x / n;
    };
    const double total = integral(1.f);
    for (const float u : {0.05f, 0.2f, 0.5f, 0.77f, 0.95f}) {
        float value = 0.f, pdf = 0.f;
        const float x = sample_catmull_rom_2d(alphas, kNodes, values, cdf, alpha, u, &value, &pdf);
        CHECK(integral(x) / total == Approx(u).margin(2e-3));
        CHECK(value == Approx(spline_at(kNodes, row, x)).epsilon(1e-3));
        CHECK(pdf == Approx(value / total).epsilon(1e-3));
    }
}

TEST_CASE("subsurface: Fresnel moments obey reciprocity and the table's albedos are ordered",
          "[subsurface][fast]") {
    // Diffuse light: what enters from outside, 1 - 2 F1(1 -> n), is n^2 times what leaves
    // from inside, 1 - 2 F1(n -> 1) (reciprocity and energy balance).
    for (const double n : {1.1, 1.33, 1.5, 2.0}) {
        const double in = 1.0 - 2.0 * fresnel_moment(1, 1.0, n);
        const double out = 1.0 - 2.0 * fresnel_moment(1, n, 1.0);
        CHECK(in == Approx(n * n * out).epsilon(2e-3));
    }
    CHECK(fresnel_moment(1, 1.0, 1.0) == Approx(0.0).margin(1e-7));
    const BssrdfTable t = BssrdfTable::compute(0.f, 1.33f);
    REQUIRE(t.rho.size() == 100);
    REQUIRE(t.radius.size() == 64);
    CHECK(t.rho_eff.front() == Approx(0.f).margin(1e-6));
    for (std::size_t i = 1; i < t.rho.size(); ++i) CHECK(t.rho_eff[i] > t.rho_eff[i - 1]);
    // A white medium: the model (not energy-exact) lets rho_eff overshoot 1 by a few per cent.
    CHECK(t.rho_eff.back() > 0.9f);
    CHECK(t.rho_eff.back() < 1.05f);
    // The effective albedo of a white medium is close to the classical dipole's total
    // diffuse reflectance (Jensen et al. 2001) for the same boundary: the models differ
    // by single scattering and the beam's spread, not by much.
    for (const float rho : {0.5f, 0.9f, 0.99f}) {
        const double A =
            (1.0 + 2.0 * fresnel_moment(1, 1.33, 1.0)) / (1.0 - 2.0 * fresnel_moment(1, 1.33, 1.0));
        const double s = std::sqrt(3.0 * (1.0 - rho));
        const double dipole = rho / 2.0 * (1.0 + std::exp(-4.0 / 3.0 * A * s)) * std::exp(-s);
        int offset = 0;
        float w[4];
        REQUIRE(catmull_rom_weights(t.rho, rho, offset, w));
        float eff = 0.f;
        for (int j = 0; j < 4; ++j)
            if (w[j] != 0.f) eff += w[j] * t.rho_eff[std::size_t(offset + j)];
        CHECK(eff == Approx(dipole).epsilon(0.25));
        CHECK(t.albedo_for(eff) == Approx(rho).epsilon(1e-3));
    }
}

TEST_CASE("subsurface: probes on a plane integrate the profile to the effective albedo",
          "[subsurface][fast]") {
    // Exit points on the plane z = 0 through po: E[Sp / pdf_sp] is the integral of Sp over
    // the plane, per channel the effective albedo of its rho (less the 0.1 % beyond r_max).
    const BssrdfTable t = BssrdfTable::compute(0.f, 1.33f);
    const RGB sigma_a{0.05f, 0.5f, 2.f}, sigma_s{4.f, 3.f, 2.f};
    const TabulatedBssrdf b(t, {0.f, 0.f, 0.f}, {0.f, 0.f, 1.f}, sigma_a, sigma_s);
    const int n = 200000;
    double sum[3] = {0, 0, 0};
    for (int i = 0; i < n; ++i) {
        BssrdfProbe probe;
        if (!b.sample_probe(
                rng::uniform(7, 1, uint64_t(i), 0),
                {rng::uniform(7, 1, uint64_t(i), 1), rng::uniform(7, 1, uint64_t(i), 2)}, probe))
            continue;
        const Vec3 d = probe.p1 - probe.p0;
        if (std::fabs(d.z) < 1e-6f || probe.p0.z * probe.p1.z > 0.f) continue;
        const Vec3 pi = probe.p0 + d * (-probe.p0.z / d.z);
        const RGB s = b.sp(pi) * (1.f / b.pdf_sp(pi, {0.f, 0.f, 1.f}));
        sum[0] += s.r;
        sum[1] += s.g;
        sum[2] += s.b;
    }
    const float sa[3] = {sigma_a.r, sigma_a.g, sigma_a.b},
                ss[3] = {sigma_s.r, sigma_s.g, sigma_s.b};
    for (int c = 0; c < 3; ++c) {
        int offset = 0;
        float w[4];
        REQUIRE(catmull_rom_weights(t.rho, ss[c] / (sa[c] + ss[c]), offset, w));
        float eff = 0.f;
        for (int j = 0; j < 4; ++j)
            if (w[j] != 0.f) eff += w[j] * t.rho_eff[std::size_t(offset + j)];
        CHECK(sum[c] / n == Approx(eff).epsilon(0.015));
    }
}

namespace {

// A slab 200 wide and 40 deep of a subsurface material under a white sky, seen straight
// down through a small window.
std::string slab_scene(const std::string& material, const std::string& renderer) {
    return R"(<scene>
  <lights><environment intensity="1"><color r="1" g="1" b="1"/></environment></lights>
  <objects>
    <box><min x="-100" y="-100" z="-40"/><max x="100" y="100" z="0"/>)" +
           material + R"(</box>
  </objects>
  <film width="8" height="8" size="0.5"/>
  <renderer type=")" +
           renderer + R"(" max_depth="50" rr_depth="50"/>
  <camera type="orthographic"><eye x="0" y="0" z="10"/><target x="0" y="0" z="0"/>
    <up x="0" y="1" z="0"/></camera>
</scene>)";
}

}  // namespace

TEST_CASE("subsurface: a slab under a white sky reflects F + (1 - F) rho_eff in volpath",
          "[subsurface][render]") {
    // With the medium given by its reflectance, rho_eff is that reflectance; straight down
    // the boundary reflects F = ((n - 1) / (n + 1))^2 and lets the rest in; the exit's
    // directional part sends all that leaves to the sky. Smooth and rough boundaries alike
    // (a rough one's F is not the smooth one's: only the smooth case is closed-form).
    const std::string material = R"(<material type="subsurface" ior="1.33">
        <reflectance r="0.2" g="0.5" b="0.8"/><mfp r="0.1" g="0.1" b="0.1"/></material>)";
    TestScene s(parse_scene(slab_scene(material, "volpath"), "slab.xml", "."));
    const RenderResult r = render_test(s, 256);
    RGB mean{0.f};
    for (const RGB& p : r.film.pixels) mean += p * (1.f / float(r.film.pixels.size()));
    const float F = std::pow(0.33f / 2.33f, 2.f);
    CHECK(mean.r == Approx(F + (1.f - F) * 0.2f).epsilon(0.02));
    CHECK(mean.g == Approx(F + (1.f - F) * 0.5f).epsilon(0.02));
    CHECK(mean.b == Approx(F + (1.f - F) * 0.8f).epsilon(0.02));
}

TEST_CASE("subsurface: materials are read, checked and refused where they cannot render",
          "[subsurface][input][fast]") {
    auto error_of = [](const std::string& material, const std::string& renderer) {
        try {
            TestScene s(parse_scene(slab_scene(material, renderer), "bad.xml", "."));
            render_test(s, 1);
        } catch (const InputError& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    using Catch::Matchers::Contains;
    const std::string good = R"(<material type="subsurface"><sigma_a r="1" g="1" b="1"/>
        <sigma_s r="2" g="2" b="2"/></material>)";
    CHECK_THAT(error_of(good, "path"), Contains("bad.xml:4") && Contains("volpath"));
    CHECK_THAT(error_of(good, "bdpt"), Contains("subsurface"));
    CHECK(error_of(good, "volpath") == "no error");
    CHECK_THAT(error_of(R"(<material type="subsurface"><sigma_a r="1" g="1" b="1"/></material>)",
                        "volpath"),
               Contains("both <sigma_a> and <sigma_s>"));
    CHECK_THAT(error_of(R"(<material type="subsurface"/>)", "volpath"), Contains("give <sigma_a>"));
    CHECK_THAT(
        error_of(R"(<material type="subsurface" g="1"><reflectance r="1" g="1" b="1"/></material>)",
                 "volpath"),
        Contains("g must be"));
    // pbrt-v4's: its defaults, and a reflectance whose albedo inverts the table.
    const Scene p = parse_pbrt_scene(R"(Film "rgb" "integer xresolution" 4 "integer yresolution" 4
Camera "perspective"
WorldBegin
Material "subsurface" "float scale" 2
Shape "sphere"
Material "subsurface" "rgb reflectance" [0.5 0.5 0.5] "float mfp" 0.25 "float eta" 1.5
Shape "sphere" "float radius" 0.5
)",
                                     "ss.pbrt", ".");
    REQUIRE(p.subsurfaces.size() == 2);
    CHECK(p.subsurfaces[1].from_reflectance);
    CHECK(p.subsurfaces[0].sigma_a.b == Approx(0.028f));
    CHECK(p.subsurfaces[0].sigma_s.r == Approx(5.1f));
    CHECK(p.subsurfaces[0].eta == Approx(1.33f));
    const Subsurface& q = p.subsurfaces[1];
    const float rho = q.sigma_s.g / (q.sigma_s.g + q.sigma_a.g);
    CHECK(q.sigma_s.g + q.sigma_a.g == Approx(4.f));
    CHECK(q.table->eta == Approx(1.5f));
    CHECK(q.table->albedo_for(0.5f) == Approx(rho));
    // A reflectance texture sets the coefficients where the path enters.
    Material textured;
    textured.texture = 0;
    textured.base_color = RGB{0.2f, 0.5f, 0.8f};
    RGB sa, ss;
    q.coefficients(textured, sa, ss);
    CHECK(ss.r / (sa.r + ss.r) == Approx(q.table->albedo_for(0.2f)));
    CHECK(ss.b / (sa.b + ss.b) == Approx(q.table->albedo_for(0.8f)));
    CHECK(sa.g + ss.g == Approx(4.f));
    // Measured media by name, in pbrt and in XML; unknown names list the known ones.
    const Scene named = parse_pbrt_scene(R"(Camera "perspective"
WorldBegin
Material "subsurface" "string name" "Skin1" "float scale" 10
Shape "sphere"
MakeNamedMedium "milk" "string type" "homogeneous" "string preset" "Wholemilk"
)",
                                         "named.pbrt", ".");
    REQUIRE(named.subsurfaces.size() == 1);
    CHECK(named.subsurfaces[0].sigma_a.r == Approx(0.32f));
    CHECK(named.subsurfaces[0].sigma_s.b == Approx(10.1f));
    CHECK(named.subsurfaces[0].table->g == 0.f);
    CHECK_THAT(error_of(R"(<material type="subsurface" preset="Skin9"/>)", "volpath"),
               Contains("Skin1") && Contains("Ketchup"));
    CHECK(error_of(R"(<material type="subsurface" preset="Marble" scale="100"/>)", "volpath") ==
          "no error");
}
