// Grid media: the density grid's trilinear lookup and its majorant grid, and delta and ratio
// tracking through a varying density against the optical depth
// integrated numerically; the XML and pbrt-v4 forms.
#include <catch2/catch.hpp>
#include <cmath>
#include <fstream>
#include <string>

#include "engine/core/error.h"
#include "engine/core/rng.h"
#include "engine/scene/pbrt_loader.h"
#include "engine/scene/xml_loader.h"
#include "engine/transport/common/medium_tracking.h"
#include "media_util.h"
#include "test_util.h"

using namespace foton;

namespace {

// A smooth, uneven density on n^3 samples over [-1, 1]^3, with empty corners.
std::shared_ptr<const DensityGrid> test_grid(int n) {
    std::vector<float> v;
    for (int z = 0; z < n; ++z)
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) {
                const float fx = (x + 0.5f) / n, fy = (y + 0.5f) / n, fz = (z + 0.5f) / n;
                const float r2 = (fx - 0.5f) * (fx - 0.5f) + (fy - 0.4f) * (fy - 0.4f) +
                                 (fz - 0.55f) * (fz - 0.55f);
                v.push_back(std::max(0.f, 1.f - 4.f * r2) * (1.5f + std::sin(9.f * fx + 4.f * fz)));
            }
    Bounds3 box;
    box.extend(Vec3{-1, -1, -1});
    box.extend(Vec3{1, 1, 1});
    return std::make_shared<const DensityGrid>(n, n, n, std::move(v), box);
}

Medium grid_medium(int n) {
    Medium m;
    m.kind = MediumKind::Grid;
    m.sigma_a = RGB{0.3f, 0.8f, 1.2f};
    m.sigma_s = RGB{1.2f, 0.6f, 0.4f};
    m.density = test_grid(n);
    return m;
}

}  // namespace

TEST_CASE("density grid: trilinear between sample centres, zero outside, majorant bounds it",
          "[media][fast]") {
    const auto g = test_grid(6);
    // At a sample's centre, the sample.
    const Vec3 c{-1.f + (2.f + 0.5f) * 2.f / 6.f, -1.f + (3.f + 0.5f) * 2.f / 6.f,
                 -1.f + (1.f + 0.5f) * 2.f / 6.f};
    CHECK(g->lookup(c) == Approx(g->sample(2, 3, 1)));
    // Half way between two centres along x, their mean.
    const Vec3 mid = c + Vec3{1.f / 6.f, 0, 0};
    CHECK(g->lookup(mid) == Approx(0.5f * (g->sample(2, 3, 1) + g->sample(3, 3, 1))));
    CHECK(g->lookup({1.01f, 0, 0}) == 0.f);
    CHECK(g->lookup({0, -1.2f, 0}) == 0.f);
    int below = 0;
    for (int i = 0; i < 100000; ++i) {
        const Vec3 p{rng::uniform(3, 1, uint64_t(i), 0) * 2.f - 1.f,
                     rng::uniform(3, 1, uint64_t(i), 1) * 2.f - 1.f,
                     rng::uniform(3, 1, uint64_t(i), 2) * 2.f - 1.f};
        const kern::GridFrame& f = g->majorant_frame();
        const uint32_t cell = f.index(f.cell_of(0, p.x), f.cell_of(1, p.y), f.cell_of(2, p.z));
        below += g->lookup(p) <= g->majorant(cell) ? 1 : 0;
    }
    CHECK(below == 100000);
}

TEST_CASE("ratio and delta tracking through a varying density equal exp(-optical depth)",
          "[media][fast]") {
    const Medium m = grid_medium(12);
    const Vec3 rays[3][2] = {{{-2, 0.1f, 0.2f}, {1, 0, 0}},
                             {{-1.5f, -1.5f, -1.5f}, {1, 1, 1}},
                             {{0.3f, 2, -0.4f}, {0, -1, 0.2f}}};
    for (int k = 0; k < 3; ++k) {
        const Vec3 o = rays[k][0], d = normalize(rays[k][1]);
        const float t_end = 3.5f;
        const RGB exact = test::exact_transmittance(m, o, d, t_end);
        const int n = 100000;
        RGB ratio{0.f}, pass{0.f};
        for (int i = 0; i < n; ++i) {
            test::Draws u{77, uint64_t(20 + k), uint64_t(i)};
            ratio += ratio_track_grid(m, o, d, t_end, u);
            test::Draws v{77, uint64_t(40 + k), uint64_t(i)};
            const FreeFlight f = delta_track_grid(m, o, d, t_end, RGB{1.f}, v);
            if (f.event == FreeFlight::Event::Pass) pass += f.weight;
        }
        INFO("ray " << k << ": exact " << exact.r << " " << exact.g << " " << exact.b);
        INFO("ratio " << ratio.r / n << " " << ratio.g / n << " " << ratio.b / n);
        INFO("delta " << pass.r / n << " " << pass.g / n << " " << pass.b / n);
        CHECK(exact.g < 0.9f);  // the ray does cross the cloud
        CHECK(ratio.r / n == Approx(exact.r).margin(0.01));
        CHECK(ratio.g / n == Approx(exact.g).margin(0.01));
        CHECK(ratio.b / n == Approx(exact.b).margin(0.01));
        CHECK(pass.r / n == Approx(exact.r).margin(0.01));
        CHECK(pass.g / n == Approx(exact.g).margin(0.01));
        CHECK(pass.b / n == Approx(exact.b).margin(0.01));
    }
}

TEST_CASE("grid media in XML and pbrt-v4, and their errors", "[media][fast]") {
    test::TempDir dir;
    {
        std::ofstream f(dir.file("d.raw"), std::ios::binary);
        const float v[8] = {0, 1, 2, 3, 4, 5, 6, 7};
        f.write(reinterpret_cast<const char*>(v), sizeof v);
    }
    auto xml = [&](const std::string& medium) {
        return "<scene><film width=\"8\" height=\"8\"/>\n<media>" + medium +
               "</media>\n<objects><sphere radius=\"1\" medium_inside=\"m\"><center x=\"0\" "
               "y=\"0\" z=\"0\"/><material type=\"interface\"/></sphere></objects>\n"
               "<renderer type=\"volpath\"/><camera><eye x=\"0\" y=\"0\" z=\"5\"/><target x=\"0\" "
               "y=\"0\" z=\"0\"/></camera></scene>";
    };
    const std::string box = "<p0 x=\"-1\" y=\"-1\" z=\"-1\"/><p1 x=\"1\" y=\"1\" z=\"1\"/>";
    const Scene s =
        parse_scene(xml("<medium name=\"m\" type=\"grid\" nx=\"2\" ny=\"2\" nz=\"2\" src=\"d.raw\">"
                        "<sigma_s r=\"1\" g=\"1\" b=\"1\"/>" +
                        box + "</medium>"),
                    "g.xml", dir.path().string());
    REQUIRE(s.media.size() == 1);
    CHECK(s.media[0].kind == MediumKind::Grid);
    CHECK(s.media[0].density->sample(1, 1, 1) == 7.f);
    CHECK(s.media[0].density->max_value() == 7.f);
    auto error_of = [&](const std::string& medium) -> std::string {
        try {
            parse_scene(xml(medium), "g.xml", dir.path().string());
        } catch (const InputError& e) {
            return e.what();
        }
        return "";
    };
    CHECK(error_of("<medium name=\"m\" type=\"grid\" nx=\"3\" ny=\"2\" nz=\"2\" src=\"d.raw\">"
                   "<sigma_s r=\"1\" g=\"1\" b=\"1\"/>" +
                   box + "</medium>")
              .find("g.xml:2: sample file 'd.raw' has 32 bytes; 12 float32 values are 48") !=
          std::string::npos);
    CHECK(error_of("<medium name=\"m\" type=\"grid\" nx=\"2\" ny=\"2\" nz=\"2\" src=\"no.raw\">"
                   "<sigma_s r=\"1\" g=\"1\" b=\"1\"/>" +
                   box + "</medium>")
              .find("sample file 'no.raw': not found") != std::string::npos);
    CHECK(error_of("<medium name=\"m\" nx=\"2\"><sigma_s r=\"1\" g=\"1\" b=\"1\"/></medium>")
              .find("'nx' belongs to a grid medium") != std::string::npos);
    // pbrt-v4's uniformgrid, placed by a scale and a translation.
    const Scene p = parse_pbrt_scene(R"(LookAt 0 0 5 0 0 0 0 1 0
Camera "perspective"
WorldBegin
AttributeBegin
  Translate 1 0 0
  Scale 2 2 2
  MakeNamedMedium "smoke" "string type" "uniformgrid" "integer nx" 2 "integer ny" 1
      "integer nz" 1 "float density" [0.5 1.5] "rgb sigma_s" [1 1 1] "rgb sigma_a" [0 0 0]
AttributeEnd
MediumInterface "smoke" ""
Material "interface"
Shape "sphere" "float radius" 3
)",
                                     "t.pbrt", ".");
    REQUIRE(p.media.size() == 1);
    CHECK(p.media[0].density->box().lo.x == Approx(1.f));
    CHECK(p.media[0].density->box().hi.x == Approx(3.f));
    CHECK(p.media[0].density->max_value() == 1.5f);
    try {
        parse_pbrt_scene(R"(WorldBegin
Rotate 30 0 1 0
MakeNamedMedium "s" "string type" "uniformgrid" "integer nx" 1 "float density" [1]
Shape "sphere"
)",
                         "t.pbrt", ".");
        FAIL("imported");
    } catch (const InputError& e) {
        CHECK(std::string(e.what()).find("t.pbrt:3: MakeNamedMedium \"s\": a grid medium placed "
                                         "by a rotation is not supported") != std::string::npos);
    }
}

TEST_CASE("smoke grid: the SIMD and scalar flight kernels give the same image, vpm agrees",
          "[media][render]") {
    TestScene s = load_scene(test::source_path("scenes/smoke.xml"));
    s.set_resolution(24, 24);
    auto render_with = [&](const char* kernel, int threads, uint32_t spp) {
        TestScene t = s;
        ParamSet p = t.renderer;
        p.set("flight_kernel", kernel, "test", 0);
        t.render = render_settings(p);
        return render_test(t, spp, threads, 6).film;
    };
    const Film simd = render_with("simd", 1, 4);
    CHECK(render_with("scalar", 1, 4).pixels == simd.pixels);
    CHECK(render_with("simd", 3, 4).pixels == simd.pixels);
    // Photons through the grid (vpm, its flights one at a time) against volpath's paths.
    const Film ref = render_with("simd", 2, 512 * test::effort());
    TestScene v = load_scene(test::source_path("scenes/smoke.xml"),
                             {{"type", "vpm"}, {"photons_per_pass", "20000"}});
    v.set_resolution(24, 24);
    const Film got = render_test(v, 32 * test::effort(), 2, 6).film;
    RGB a{0.f}, b{0.f};
    for (std::size_t i = 0; i < ref.pixels.size(); ++i) {
        a += ref.pixels[i];
        b += got.pixels[i];
    }
    INFO("volpath " << a.r << " " << a.g << " " << a.b << ", vpm " << b.r << " " << b.g << " "
                    << b.b);
    CHECK(b.r == Approx(a.r).epsilon(0.03));
    CHECK(b.g == Approx(a.g).epsilon(0.03));
    CHECK(b.b == Approx(a.b).epsilon(0.03));
}
