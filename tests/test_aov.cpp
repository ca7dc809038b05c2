// The AOVs (film/aov.h): first-hit layers against analytic values on a plane, the variance
// layer against the sample variance of the very samples the image averages, determinism
// across thread counts, the EXR channels, and bad requests.
#include <catch2/catch.hpp>
#include <cmath>

#include "engine/film/image_io.h"
#include "engine/scene/xml_loader.h"
#include "test_util.h"

using namespace foton;

namespace {

// A matte plane z = 0 of reflectance kd * (1, 0.5, 0.25) over x < 0 only, seen head-on from
// z = 10 by a perspective camera: the left half of the image hits it, the right half misses.
TestScene half_plane(const std::string& renderer) {
    return parse_scene(R"(<scene><lights><point intensity="10"><position x="0" y="0" z="5"/>
        </point></lights><objects>
      <quad><corner x="-50" y="-50" z="0"/><edge1 x="50" y="0" z="0"/><edge2 x="0" y="100" z="0"/>
        <material type="matte" c_diffuse="0.8"><base_color r="1" g="0.5" b="0.25"/></material>
      </quad></objects>
      <film width="24" height="16" size="0.01"/>)" +
                           renderer + R"(
      <camera type="perspective" d="1"><eye x="0" y="0" z="10"/><target x="0" y="0" z="0"/>
        <up x="0" y="1" z="0"/></camera></scene>)",
                       "half-plane.xml", ".");
}

const AovLayer& layer(const RenderResult& r, const char* name) {
    const AovLayer* l = find_aov(r.aovs, name);
    REQUIRE(l != nullptr);
    return *l;
}

}  // namespace

TEST_CASE("first-hit AOVs of a plane equal their analytic values", "[aov]") {
    for (const char* integrator : {"path", "light", "bdpt", "sppm", "raytracer"}) {
        CAPTURE(integrator);
        TestScene s = half_plane(std::string("<renderer type=\"") + integrator +
                                 "\" aov=\"albedo,normal,depth,position\"/>");
        const RenderResult r = render_test(s, 4, 2);
        REQUIRE(r.aovs.size() == 4);
        const AovLayer &albedo = layer(r, "albedo"), &normal = layer(r, "normal"),
                       &depth = layer(r, "depth"), &position = layer(r, "position");
        CHECK(normal.channels ==
              std::vector<std::string>{"N.X", "N.Y", "N.Z", "Ns.X", "Ns.Y", "Ns.Z"});
        CHECK(depth.channels == std::vector<std::string>{"Z"});
        int hit = 0, missed = 0;
        for (std::size_t p = 0; p < r.film.pixels.size(); ++p) {
            const float z = depth.at(p, 0);
            if (std::isinf(z)) {
                ++missed;
                for (int c = 0; c < 3; ++c) CHECK(albedo.at(p, c) == 0.f);
                continue;
            }
            // Pixels on the plane's edge are partly covered: their albedo is a fraction.
            if (!(albedo.at(p, 0) > 0.79f)) continue;
            ++hit;
            CHECK(albedo.at(p, 0) == Approx(0.8f).epsilon(1e-6));
            CHECK(albedo.at(p, 1) == Approx(0.4f).epsilon(1e-6));
            CHECK(albedo.at(p, 2) == Approx(0.2f).epsilon(1e-6));
            // The plane faces the camera, whose view axis is camera space's +z.
            for (int c = 0; c < 6; ++c) CHECK(normal.at(p, c) == (c % 3 == 2 ? -1.f : 0.f));
            CHECK(z == Approx(10.f).epsilon(1e-5));
            CHECK(position.at(p, 2) == Approx(10.f).epsilon(1e-5));
            // On the plane x < 0 in world space, seen from +z with y up: camera space x > 0
            // is the world's -x (the image's left is the plane's side).
            CHECK(std::abs(position.at(p, 0)) < 10.f * 0.12f + 1e-3f);
        }
        CHECK(hit >= int(r.film.pixels.size()) * 2 / 5);
        CHECK(missed >= int(r.film.pixels.size()) * 2 / 5);
    }
}

TEST_CASE("the variance AOV is the sample variance of the pixel's samples", "[aov]") {
    TestScene s = load_scene(test::source_path("scenes/cornell-box.xml"));
    s.set_resolution(24, 24);
    s.render = render_settings(s);
    s.render.integrator = "path";
    s.render.aovs = kAovVariance | kAovSamples;
    const auto accel = make_intersector(s, s.accel);
    RenderOptions opt;
    opt.spp = 1;
    opt.max_passes = 12;
    opt.threads = 2;
    // Each pass adds one sample per pixel: the running means give back every sample.
    std::vector<std::vector<double>> samples(s.film.width * s.film.height * 3);
    std::vector<RGB> last(samples.size() / 3, RGB{0.f});
    uint32_t passes = 0;
    opt.on_pass = [&](const Film& f, const PassReport&) {
        ++passes;
        for (std::size_t p = 0; p < last.size(); ++p) {
            const float* now = &f.pixels[p].r;
            const float* before = &last[p].r;
            for (int c = 0; c < 3; ++c)
                samples[p * 3 + c].push_back(double(passes) * now[c] -
                                             double(passes - 1) * before[c]);
            last[p] = f.pixels[p];
        }
    };
    const RenderResult r = render(s, s.render, *accel, opt);
    REQUIRE(passes == 12);
    const AovLayer& var = layer(r, "variance");
    int noisy = 0;
    for (std::size_t i = 0; i < samples.size(); ++i) {
        double mean = 0.0, m2 = 0.0;
        for (double x : samples[i]) mean += x;
        mean /= double(samples[i].size());
        for (double x : samples[i]) m2 += (x - mean) * (x - mean);
        const double expected = m2 / double(samples[i].size() - 1);
        CAPTURE(i, mean);
        // The samples come back from float means: a few float ulps of the pixel's scale.
        CHECK(var.values[i] == Approx(expected).epsilon(1e-3).margin(1e-5 * (1.0 + mean * mean)));
        noisy += expected > 1e-3;
    }
    CHECK(noisy > int(samples.size() / 4));
    for (uint32_t n : r.samples_per_pixel) CHECK(n == 12);
}

TEST_CASE("AOVs are bit-identical for any thread count", "[aov]") {
    TestScene s = load_scene(test::source_path("scenes/cornell-box.xml"));
    s.set_resolution(32, 24);
    s.render = render_settings(s);
    s.render.integrator = "path";
    s.render.aovs = kAovAll & ~kAovComponents;
    const RenderResult a = render_test(s, 3, 1), b = render_test(s, 3, 3);
    REQUIRE(a.aovs.size() == 5);
    REQUIRE(b.aovs.size() == a.aovs.size());
    for (std::size_t k = 0; k < a.aovs.size(); ++k) {
        CAPTURE(a.aovs[k].name);
        CHECK(std::memcmp(a.aovs[k].values.data(), b.aovs[k].values.data(),
                          a.aovs[k].values.size() * sizeof(float)) == 0);
    }
}

TEST_CASE("aov settings: all, unknown names, variance without pixel samples", "[aov]") {
    auto settings = [](const std::string& renderer) {
        return render_settings(half_plane(renderer));
    };
    CHECK(settings("<renderer type=\"path\" aov=\"all\"/>").aovs == (kAovAll & ~kAovComponents));
    CHECK(settings("<renderer type=\"photon\" aov=\"all\"/>").aovs == kAovAll);
    CHECK(settings("<renderer type=\"path\" aov=\" depth , albedo\"/>").aovs ==
          (kAovDepth | kAovAlbedo));
    // `all` for an integrator that splats light paths: everything but the variance.
    CHECK(settings("<renderer type=\"bdpt\" aov=\"all\"/>").aovs ==
          (kAovAll & ~kAovVariance & ~kAovComponents));
    CHECK_THROWS_WITH(
        settings("<renderer type=\"path\" aov=\"albedo,colour\"/>"),
        Catch::Contains("half-plane.xml:6") && Catch::Contains("unknown AOV 'colour'"));
    CHECK_THROWS_WITH(settings("<renderer type=\"vcm\" aov=\"variance\"/>"),
                      Catch::Contains("variance AOV needs pixel samples"));
}

TEST_CASE("foton render --aov writes the layers as EXR channels", "[aov][cli]") {
    test::TempDir dir;
    const std::string out = dir.file("plane.exr");
    const test::FotonRun run =
        test::run_foton("render " + test::source_path("scenes/cornell-box.xml") +
                        " --width 16 --height 12 --spp 2 --integrator path --aov all -q -o " + out);
    REQUIRE(run.code == 0);
    int w = 0, h = 0;
    const std::vector<float> v = read_exr_channels(
        out, {"R", "Albedo.G", "N.Z", "Ns.Z", "Z", "P.Z", "Variance.B", "samples"}, w, h);
    REQUIRE(w == 16);
    REQUIRE(h == 12);
    for (int p = 0; p < w * h; ++p) {
        const float* px = &v[std::size_t(p) * 8];
        CHECK(px[1] >= 0.f);
        CHECK(px[2] <= 0.f);  // normals face the camera (view axis +z)
        CHECK(px[4] > 0.f);   // everything in the box is in front of the camera
        CHECK(px[4] == px[5]);
        CHECK(px[6] >= 0.f);
        CHECK(px[7] == 2.f);
    }
    const test::FotonRun bad = test::run_foton(
        "render " + test::source_path("scenes/cornell-box.xml") +
        " --width 8 --height 8 --integrator bdpt --aov variance -q -o " + dir.file("bad.exr"));
    CHECK(bad.code == 2);
    CHECK(bad.output.find("--aov") != std::string::npos);
    CHECK(bad.output.find("variance AOV needs pixel samples") != std::string::npos);
    CHECK(!std::filesystem::exists(dir.file("bad.exr")));
}

TEST_CASE("bdpt and vcm's per-strategy images add up to the image", "[aov][bidir]") {
    for (const char* integrator : {"bdpt", "vcm"}) {
        CAPTURE(integrator);
        TestScene s = load_scene(test::source_path("scenes/cornell-caustics.xml"));
        s.set_resolution(24, 20);
        s.render = render_settings(s);
        s.render.integrator = integrator;
        const RenderResult plain = render_test(s, 2, 2);
        s.render.bidir.strategy_images = 4;
        const RenderResult r = render_test(s, 2, 2);
        // Splitting changes nothing in the image.
        CHECK(std::memcmp(plain.film.pixels.data(), r.film.pixels.data(),
                          r.film.pixels.size() * sizeof(RGB)) == 0);
        // Paths of 2, 3 and 4 vertices: 2 + 3 + 4 strategies, the longer paths' and (vcm)
        // the merges.
        const bool vcm = std::string(integrator) == "vcm";
        REQUIRE(r.aovs.size() == (vcm ? 11u : 10u));
        CHECK(r.aovs.front().name == "strategy_s0_t2");
        CHECK(r.aovs[4].name == "strategy_s2_t1");
        CHECK(r.aovs[9].name == "strategy_longer");
        if (vcm) CHECK(r.aovs[10].name == "strategy_merges");
        std::vector<double> total(r.aovs.size(), 0.0);
        for (std::size_t p = 0; p < r.film.pixels.size(); ++p) {
            const float* image = &r.film.pixels[p].r;
            for (int c = 0; c < 3; ++c) {
                double sum = 0.0;
                for (std::size_t l = 0; l < r.aovs.size(); ++l) {
                    sum += r.aovs[l].at(p, std::size_t(c));
                    total[l] += r.aovs[l].at(p, std::size_t(c));
                }
                CHECK(sum == Approx(image[c]).epsilon(1e-4).margin(1e-6));
            }
        }
        // The light seen directly (s = 0, t = 2), next event estimation at the first hit
        // (s = 1, t = 2), light tracing to the camera (s = 2, t = 1) and the longer paths all
        // add light to this scene.
        CHECK(r.aovs[3].name == "strategy_s1_t2");
        for (const std::size_t l :
             {std::size_t(0), std::size_t(3), std::size_t(4), std::size_t(9)}) {
            CAPTURE(r.aovs[l].name);
            CHECK(total[l] > 0.0);
        }
    }
}

TEST_CASE("strategy_images: a bidirectional setting, at least 2", "[aov][bidir]") {
    auto settings = [](const std::string& renderer) {
        return render_settings(half_plane(renderer));
    };
    CHECK(settings("<renderer type=\"bdpt\" strategy_images=\"5\"/>").bidir.strategy_images == 5);
    CHECK_THROWS_WITH(settings("<renderer type=\"bdpt\" strategy_images=\"1\"/>"),
                      Catch::Contains("half-plane.xml:6") && Catch::Contains("at least 2"));
    CHECK_THROWS_WITH(settings("<renderer type=\"vcm\" strategy_images=\"40\"/>"),
                      Catch::Contains("strategy_images"));
    const RenderSettings path = settings("<renderer type=\"path\" strategy_images=\"3\"/>");
    CHECK(path.bidir.strategy_images == 0);
    REQUIRE(!path.warnings.empty());
    CHECK(path.warnings.back().find("applies to") != std::string::npos);
}

TEST_CASE("photon mapping's components add up to the image", "[aov][photon]") {
    struct Case {
        const char* what;
        std::vector<std::pair<std::string, std::string>> set;
        const char* last;
    };
    const Case cases[] = {
        {"final gather", {}, "indirect"},
        {"adaptive", {{"adaptive", "true"}, {"adaptive_max_spp", "8"}}, "indirect"},
        {"irradiance cache", {{"indirect", "irradiance_cache"}}, "indirect"},
        {"direct visualisation", {{"mode", "direct_visualisation"}}, "photon_map"},
    };
    for (const Case& c : cases) {
        CAPTURE(c.what);
        RendererOverrides set{{"type", "photon"},
                              {"global_photons", "20000"},
                              {"caustic_photons", "20000"},
                              {"gather_rays", "8"}};
        set.insert(set.end(), c.set.begin(), c.set.end());
        TestScene s = load_scene(test::source_path("scenes/cornell-caustics.xml"), set);
        s.set_resolution(24, 20);
        s.render = render_settings(s);
        const RenderResult plain = render_test(s, 2, 2);
        s.render.aovs = kAovComponents;
        const RenderResult r = render_test(s, 2, 2);
        CHECK(std::memcmp(plain.film.pixels.data(), r.film.pixels.data(),
                          r.film.pixels.size() * sizeof(RGB)) == 0);
        REQUIRE(r.aovs.size() == 4);
        CHECK(r.aovs[0].name == "emitted");
        CHECK(r.aovs[3].name == c.last);
        CHECK(r.aovs[3].channels.front() == std::string(c.last) + ".R");
        std::vector<double> total(4, 0.0);
        for (std::size_t p = 0; p < r.film.pixels.size(); ++p)
            for (int ch = 0; ch < 3; ++ch) {
                double sum = 0.0;
                for (std::size_t l = 0; l < 4; ++l) {
                    sum += r.aovs[l].at(p, std::size_t(ch));
                    total[l] += r.aovs[l].at(p, std::size_t(ch));
                }
                CHECK(sum == Approx((&r.film.pixels[p].r)[ch]).epsilon(1e-4).margin(1e-6));
            }
        // The light is seen directly, and in final gathering the other three carry light.
        CHECK(total[0] > 0.0);
        if (std::string(c.last) == "indirect")
            for (std::size_t l = 1; l < 4; ++l) CHECK(total[l] > 0.0);
        else
            CHECK(total[3] > 0.0);
    }
    // Only photon mapping has them; `all` leaves them out elsewhere.
    CHECK_THROWS_WITH(render_settings(half_plane("<renderer type=\"path\" aov=\"components\"/>")),
                      Catch::Contains("components AOV needs"));
    CHECK((render_settings(half_plane("<renderer type=\"path\" aov=\"all\"/>")).aovs &
           kAovComponents) == 0);
}
