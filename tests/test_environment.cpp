// The environment light: the equal-area mapping, the piecewise-constant 2D density, chi-square
// tests of the map's directions against its pdf (lat-long and equal-area, alone and through
// the light set), the map's integral, importance sampling against uniform sampling, the
// furnace (a diffuse sphere under a constant sky) for every integrator, and bad input.
#include <catch2/catch.hpp>
#include <cmath>

#include "chi_square.h"
#include "engine/accel/intersector.h"
#include "engine/core/distribution.h"
#include "engine/core/error.h"
#include "engine/core/rng.h"
#include "engine/film/image_io.h"
#include "engine/scene/light_set.h"
#include "engine/scene/xml_loader.h"
#include "engine/transport/registry/render.h"
#include "test_util.h"

using namespace foton;

namespace {

// A sky with a small bright sun, a gradient towards the horizon and a black band: a density
// with sharp features and zero cells. Square when `square` (for the equal-area mapping).
TextureImage sun_sky(bool square) {
    TextureImage img;
    img.path = "sun_sky";
    img.width = square ? 64 : 96;
    img.height = square ? 64 : 48;
    img.texels.resize(std::size_t(img.width) * std::size_t(img.height));
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
            const float fy = (float(y) + 0.5f) / float(img.height);
            const float fx = (float(x) + 0.5f) / float(img.width);
            RGB c = RGB{0.2f + 0.6f * fy, 0.3f + 0.4f * fy, 0.9f - 0.5f * fy};
            if (fx > 0.8f && fx < 0.9f) c = RGB{0.f};  // a black band
            const float dx = fx - 0.3f, dy = fy - 0.25f;
            if (dx * dx + dy * dy < 0.0025f) c = RGB{400.f, 380.f, 300.f};  // the sun
            img.texels[std::size_t(y) * std::size_t(img.width) + std::size_t(x)] = c;
        }
    return img;
}

Environment sun_environment(EnvMapping m) {
    return Environment::image(sun_sky(m == EnvMapping::EqualArea), m, RGB{1.f},
                              normalize(Vec3{0.2f, 1.f, 0.1f}), Vec3{0, 0, 1});
}

Vec3 random_direction(uint64_t i) {
    return warp::uniform_sphere({rng::uniform(9, i, 0, 0), rng::uniform(9, i, 0, 1)});
}

}  // namespace

TEST_CASE("the equal-area mapping is a bijection between the square and the sphere", "[env]") {
    for (uint64_t i = 0; i < 20000; ++i) {
        const Vec3 d = random_direction(i);
        const Point2 s = equal_area_sphere_to_square(d);
        REQUIRE(s.x >= 0.f);
        REQUIRE(s.x <= 1.f);
        REQUIRE(s.y >= 0.f);
        REQUIRE(s.y <= 1.f);
        const Vec3 back = equal_area_square_to_sphere(s);
        REQUIRE(length(back - d) < 2e-3f);
        REQUIRE(std::fabs(length(back) - 1.f) < 1e-5f);
    }
}

TEST_CASE("Distribution2D draws its cells in proportion to their weights", "[env]") {
    const int nu = 7, nv = 5;
    std::vector<float> w(std::size_t(nu * nv));
    for (std::size_t i = 0; i < w.size(); ++i) w[i] = float((i * 37) % 11);  // zeros included
    const Distribution2D d(w, nu, nv);
    double total = 0.0;
    for (float x : w) total += x;
    std::vector<double> count(w.size(), 0.0);
    const int n = 200000;
    for (int i = 0; i < n; ++i) {
        float pdf;
        const Point2 p =
            d.sample({rng::uniform(3, uint64_t(i), 0, 0), rng::uniform(3, uint64_t(i), 0, 1)}, pdf);
        REQUIRE(pdf > 0.f);
        REQUIRE(pdf == d.pdf(p));
        const int c = std::min(nu - 1, int(p.x * nu)), r = std::min(nv - 1, int(p.y * nv));
        count[std::size_t(r * nu + c)] += 1.0;
    }
    double chi2 = 0.0;
    int dof = -1;
    for (std::size_t i = 0; i < w.size(); ++i) {
        const double expected = n * double(w[i]) / total;
        if (expected == 0.0) {
            CHECK(count[i] == 0.0);
            continue;
        }
        chi2 += (count[i] - expected) * (count[i] - expected) / expected;
        ++dof;
    }
    const double p = test::gamma_q(0.5 * dof, 0.5 * chi2);
    INFO("chi2 " << chi2 << " dof " << dof << " p " << p);
    CHECK(p > 1e-3);
    CHECK(d.integral() == Approx(total / (nu * nv)).epsilon(1e-6));
    CHECK_THROWS(Distribution2D(std::vector<float>(6, 0.f), 3, 2));
}

TEST_CASE("chi-square: environment map directions follow the map's pdf", "[env]") {
    for (EnvMapping m : {EnvMapping::LatLong, EnvMapping::EqualArea}) {
        const Environment env = sun_environment(m);
        INFO(env_mapping_name(m));
        // Directions are binned about the map's up axis, where the lat-long rows are.
        test::ChiSquareSetup setup;
        setup.axis = normalize(Vec3{0.2f, 1.f, 0.1f});
        setup.samples = 300000;
        setup.quad = 40;  // the sun's edge needs a fine quadrature
        // A direction drawn on a texel's edge may round into its neighbour, whose density
        // differs: allow a few in a thousand such.
        int mismatched = 0;
        const auto r = test::chi_square(
            setup,
            [&](int i, Vec3& w) {
                float pdf;
                w = env.sample(
                    Vec3{},
                    {rng::uniform(5, uint64_t(i), 0, 0), rng::uniform(5, uint64_t(i), 0, 1)}, pdf);
                REQUIRE(pdf > 0.f);
                // The density and the radiance where it was drawn agree with the lookups.
                if (std::fabs(pdf - env.pdf(Vec3{}, w)) > 2e-3f * pdf ||
                    !(env.Le(Vec3{}, w).luminance() > 0.f))
                    ++mismatched;
                return true;
            },
            [&](const Vec3& w) { return double(env.pdf(Vec3{}, w)); });
        INFO(r.summary());
        CHECK(mismatched < setup.samples / 1000);
        CHECK(r.p_value > 1e-3);
        CHECK(r.expected_total == Approx(1.0).epsilon(0.01));
    }
}

TEST_CASE("the light set samples the environment as its pdf says, selection included", "[env]") {
    Scene s = parse_scene(R"(<scene><lights>
      <point intensity="30"><position x="0" y="5" z="0"/></point></lights><objects>
      <sphere radius="1"><center x="0" y="0" z="0"/><material type="lambert"/></sphere>
    </objects><film width="8" height="8"/>
    <camera><eye x="0" y="0" z="-8"/><target x="0" y="0" z="0"/></camera></scene>)",
                          "env.xml", ".");
    s.environment = sun_environment(EnvMapping::LatLong);
    const LightSet ls(s);
    REQUIRE(ls.size() == 2);
    REQUIRE(ls.environment() == 1);
    const Emitter& e = ls.emitter(1);
    CHECK(e.type == EmitterType::Environment);
    CHECK(!e.is_delta());
    CHECK(e.is_infinite());
    const Vec3 p{0.f, 2.f, 0.f};
    for (uint64_t i = 0; i < 2000; ++i) {
        LightSample smp;
        if (!ls.sample_li(1, p, {rng::uniform(6, i, 0, 0), rng::uniform(6, i, 0, 1)}, 0.f, smp))
            continue;
        REQUIRE(std::isinf(smp.dist));
        REQUIRE(smp.pdf == Approx(s.environment->pdf(Vec3{}, smp.wi)).epsilon(2e-3));
        REQUIRE(ls.environment_pdf(smp.wi) == Approx(ls.pmf(1) * smp.pdf).epsilon(2e-3));
        REQUIRE(smp.Li.r == s.environment->Le(Vec3{}, smp.wi).r);
        // Emitted rays start outside the scene and head into it.
        EmissionSample es;
        REQUIRE(ls.sample_le(1, {rng::uniform(7, i, 0, 0), rng::uniform(7, i, 0, 1)},
                             {rng::uniform(7, i, 0, 2), rng::uniform(7, i, 0, 3)}, 0.f, es));
        REQUIRE(length(es.p) > std::sqrt(3.f));
        REQUIRE(dot(es.dir, -es.p) > 0.f);
    }
}

TEST_CASE("the environment's integral is its radiance over the sphere", "[env]") {
    for (EnvMapping m : {EnvMapping::LatLong, EnvMapping::EqualArea}) {
        const Environment env = sun_environment(m);
        // Uniform directions: E[Le / (1 / 4 pi)] is the integral.
        const int n = 400000;
        double sum[3] = {0, 0, 0};
        for (int i = 0; i < n; ++i) {
            const RGB L = env.Le(Vec3{}, random_direction(uint64_t(i)));
            sum[0] += L.r;
            sum[1] += L.g;
            sum[2] += L.b;
        }
        const double k = 4.0 * kPi / n;
        INFO(env_mapping_name(m));
        CHECK(sum[0] * k == Approx(env.integral().r).epsilon(0.03));
        CHECK(sum[1] * k == Approx(env.integral().g).epsilon(0.03));
        CHECK(sum[2] * k == Approx(env.integral().b).epsilon(0.03));
    }
}

TEST_CASE("importance sampling the map beats uniform sampling at equal samples", "[env]") {
    // Irradiance on a surface facing the map's up axis, estimated with 16 samples, 400 times.
    const Environment env = sun_environment(EnvMapping::LatLong);
    const Vec3 n = normalize(Vec3{0.2f, 1.f, 0.1f});
    auto irradiance = [&](bool importance, uint64_t trial, int count) {
        double e = 0.0;
        for (int k = 0; k < count; ++k) {
            const Point2 u{rng::uniform(8, trial, uint64_t(k), 0),
                           rng::uniform(8, trial, uint64_t(k), 1)};
            float pdf;
            const Vec3 w = importance ? env.sample(Vec3{}, u, pdf) : warp::uniform_sphere(u);
            if (!importance) pdf = warp::kUniformSpherePdf;
            const float c = dot(w, n);
            if (c > 0.f && pdf > 0.f) e += double(env.Le(Vec3{}, w).luminance() * c / pdf);
        }
        return e / count;
    };
    const double truth = irradiance(true, 1u << 30, 2000000);
    double se_imp = 0.0, se_uni = 0.0;
    const int trials = 400;
    for (int t = 0; t < trials; ++t) {
        const double a = irradiance(true, uint64_t(t), 16) - truth;
        const double b = irradiance(false, uint64_t(t), 16) - truth;
        se_imp += a * a;
        se_uni += b * b;
    }
    const double rmse_imp = std::sqrt(se_imp / trials), rmse_uni = std::sqrt(se_uni / trials);
    INFO("irradiance " << truth << ", RMSE importance " << rmse_imp << ", uniform " << rmse_uni
                       << ", ratio " << rmse_uni / rmse_imp);
    CHECK(rmse_imp * 3.0 < rmse_uni);
}

namespace {

// A diffuse sphere of reflectance (0.8, 0.5, 0.2) under a constant sky of radiance 1: being
// convex it sees only the sky, so every point of it has radiance rho exactly.
TestScene furnace_scene(const std::string& integrator) {
    TestScene s(parse_scene(R"(<scene>
      <lights><environment intensity="1"/></lights>
      <objects><sphere radius="1"><center x="0" y="0" z="0"/>
        <material type="lambert"><reflectance r="0.8" g="0.5" b="0.2"/></material></sphere>
      </objects><film width="32" height="32"/>
      <renderer type=")" + integrator +
                                R"(" max_depth="8"/>
      <camera fov="20"><eye x="0" y="0" z="-10"/><target x="0" y="0" z="0"/></camera></scene>)",
                            "furnace.xml", "."));
    return s;
}

// Mean over the pixels whose centre sees the sphere within 0.8 of its radius.
RGB sphere_mean(const Scene& s, const Film& f) {
    double sum[3] = {0, 0, 0};
    int n = 0;
    for (int y = 0; y < f.height; ++y)
        for (int x = 0; x < f.width; ++x) {
            Vec3 o, d;
            s.camera.generate(float(x) + 0.5f, float(y) + 0.5f, o, d);
            const float t = -dot(o, d);
            if (length(o + d * t) > 0.8f) continue;
            const RGB& c = f.pixels[std::size_t(y) * std::size_t(f.width) + std::size_t(x)];
            sum[0] += c.r;
            sum[1] += c.g;
            sum[2] += c.b;
            ++n;
        }
    REQUIRE(n > 100);
    return RGB(float(sum[0] / n), float(sum[1] / n), float(sum[2] / n));
}

}  // namespace

TEST_CASE("furnace: a diffuse sphere under a constant sky has radiance rho", "[env][integrator]") {
    struct Case {
        const char* integrator;
        uint32_t spp;
        float tolerance;
    };
    // Light tracing reaches a pixel of the sphere far less often than camera paths do.
    const Case cases[] = {{"path", 1024, 0.01f},      {"distributed", 1024, 0.01f},
                          {"raytracer", 1024, 0.01f}, {"light", 2048, 0.01f},
                          {"photon", 1024, 0.01f},    {"sppm", 1024, 0.01f}};
    for (const Case& c : cases) {
        TestScene s = furnace_scene(c.integrator);
        const auto acc = make_intersector(s, s.accel);
        RenderOptions opt;
        opt.spp = c.spp;
        const RenderResult r = render(s, s.render, *acc, opt);
        const RGB m = sphere_mean(s, r.film);
        INFO(c.integrator << ": " << m.r << " " << m.g << " " << m.b);
        CHECK(m.r == Approx(0.8f).epsilon(c.tolerance));
        CHECK(m.g == Approx(0.5f).epsilon(c.tolerance));
        CHECK(m.b == Approx(0.2f).epsilon(c.tolerance));
        // The camera integrators see the sky around the sphere; the light tracer cannot
        // (a point at infinity cannot be joined to a pinhole).
        const RGB corner = r.film.pixels[0];
        CHECK(corner.r == (std::string(c.integrator) == "light" ? 0.f : 1.f));
    }
}

TEST_CASE("bad environment input is reported at its line", "[env][bad-input]") {
    test::TempDir dir;
    auto load = [&](const std::string& lights, const std::string& extra = "") {
        return parse_scene("<scene>" + extra + "\n<lights>\n" + lights + R"(</lights>
          <objects><sphere radius="1"><center x="0" y="0" z="0"/><material type="lambert"/></sphere>
          </objects><film width="8" height="8"/>
          <camera><eye x="0" y="0" z="-8"/><target x="0" y="0" z="0"/></camera></scene>)",
                           "env.xml", dir.path().string());
    };
    auto fails_with = [&](const std::string& lights, const std::string& what,
                          const std::string& extra = "") {
        try {
            load(lights, extra);
            FAIL("accepted: " << lights);
        } catch (const InputError& e) {
            INFO(e.what());
            CHECK(std::string(e.what()).find(what) != std::string::npos);
        }
    };
    fails_with(R"(<environment src="missing.exr"/>)", "env.xml:3: environment map 'missing.exr'");
    fails_with(R"(<environment><portal><corner x="0" y="0" z="0"/></portal></environment>)",
               "a <portal> has 4 <corner>s");
    fails_with(
        R"(<environment src="sky.hdr"><portal><corner x="0" y="0" z="0"/><corner x="0" y="1" z="0"/><corner x="1" y="1" z="0"/><corner x="1" y="0" z="0"/></portal></environment>)",
        "mapping=\"equalarea\"");
    fails_with(R"(<environment intensity="-1"/>)", "must not be negative");
    fails_with(R"(<environment mapping="cube" src="a.exr"/>)", "unknown environment mapping");
    fails_with(R"(<environment mapping="latlong"/>)", "give src or leave them");
    fails_with(R"(<environment/>)", "not both", R"(<background r="0" g="0" b="0"/>)");
    // A map that is not square for the equal-area mapping, and a black one.
    Film wide(8, 4);
    for (RGB& p : wide.pixels) p = RGB{1.f};
    write_exr(dir.file("wide.exr"), wide, {});
    fails_with(R"(<environment src="wide.exr" mapping="equalarea"/>)", "must be square, not 8x4");
    Film black(8, 4);
    write_exr(dir.file("black.exr"), black, {});
    fails_with(R"(<environment src="black.exr"/>)", "black");
    // A good one loads, oriented.
    const Scene ok = load(R"(<environment src="wide.exr" intensity="2"><up x="0" y="0" z="1"/>
      <front x="1" y="0" z="0"/></environment>)");
    REQUIRE(ok.environment);
    CHECK(ok.environment->Le({}, {0, 0, 1}).r == 2.f);
}

TEST_CASE("uniform and importance sampling of a map converge to the same image",
          "[env][integrator]") {
    // A smooth map (no sun, so uniform sampling converges at this size).
    test::TempDir dir;
    Film sky(32, 16);
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 32; ++x)
            sky.pixels[std::size_t(y * 32 + x)] =
                RGB{0.2f + 0.05f * float(y), 0.5f, 1.2f - 0.06f * float(y)} * (x < 16 ? 1.f : 0.4f);
    write_exr(dir.file("sky.exr"), sky);
    RGB means[2];
    for (int uniform = 0; uniform < 2; ++uniform) {
        TestScene s(
            parse_scene(std::string(R"(<scene><lights><environment src="sky.exr" sampling=")") +
                            (uniform ? "uniform" : "importance") + R"("/></lights>
          <objects><sphere radius="1"><center x="0" y="0" z="0"/>
            <material type="lambert"><reflectance r="0.8" g="0.8" b="0.8"/></material></sphere>
          </objects><film width="32" height="32"/><renderer type="path" max_depth="4"/>
          <camera fov="20"><eye x="0" y="0" z="-10"/><target x="0" y="0" z="0"/></camera></scene>)",
                        "env.xml", dir.path().string()));
        CHECK(s.environment->uniform_sampling() == (uniform == 1));
        const auto acc = make_intersector(s, s.accel);
        RenderOptions opt;
        opt.spp = 512;
        means[uniform] = sphere_mean(s, render(s, s.render, *acc, opt).film);
    }
    INFO("importance " << means[0].r << " " << means[0].g << " " << means[0].b << ", uniform "
                       << means[1].r << " " << means[1].g << " " << means[1].b);
    CHECK(means[1].r == Approx(means[0].r).epsilon(0.01));
    CHECK(means[1].g == Approx(means[0].g).epsilon(0.01));
    CHECK(means[1].b == Approx(means[0].b).epsilon(0.01));
}
