// RGB grid media (pbrt-v4's rgbgrid) and emitting grid media: the coefficients at a point, the
// majorant bound, ratio and delta tracking against the per-channel optical depth, a camera
// inside an emitting grid seeing Le, and the XML and pbrt-v4 forms with their errors.
#include <catch2/catch.hpp>
#include <cmath>
#include <fstream>
#include <string>

#include "engine/core/error.h"
#include "engine/core/rng.h"
#include "engine/film/metrics.h"
#include "engine/scene/pbrt/spectrum.h"
#include "engine/scene/pbrt_loader.h"
#include "engine/scene/xml_loader.h"
#include "engine/transport/common/medium_tracking.h"
#include "media_util.h"
#include "test_util.h"

using namespace foton;

namespace {

Bounds3 unit_box() {
    Bounds3 b;
    b.extend(Vec3{-1, -1, -1});
    b.extend(Vec3{1, 1, 1});
    return b;
}

// A chromatic medium on n^3 samples over [-1, 1]^3: red absorbs on one side, blue scatters on
// the other, so the channels' optical depths differ along every ray.
Medium rgb_medium(int n, float scale) {
    std::vector<RGB> sa, ss;
    std::vector<float> bound;
    for (int z = 0; z < n; ++z)
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) {
                const float fx = (x + 0.5f) / n, fy = (y + 0.5f) / n, fz = (z + 0.5f) / n;
                sa.push_back(RGB{2.f * fx, 0.3f + fy * fz, 0.1f});
                ss.push_back(RGB{0.2f, 0.5f * fy, 1.5f * (1.f - fx) + std::sin(5.f * fz)});
                bound.push_back((sa.back() + ss.back()).max_component());
            }
    Medium m;
    m.kind = MediumKind::RGBGrid;
    m.grid_scale = scale;
    m.rgb_sigma_a = std::make_shared<const RGBGrid>(n, n, n, sa, unit_box());
    m.rgb_sigma_s = std::make_shared<const RGBGrid>(n, n, n, ss, unit_box());
    m.density = std::make_shared<const DensityGrid>(n, n, n, bound, unit_box());
    return m;
}

std::string error_of(const std::function<void()>& load) {
    try {
        load();
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST_CASE(
    "rgbgrid: coefficients at a point are the grids' trilinear values, bounded by the "
    "majorant grid",
    "[media][fast]") {
    const Medium m = rgb_medium(5, 1.5f);
    // At a sample's centre, the sample times the scale.
    const Vec3 c{-1.f + (1.f + 0.5f) * 2.f / 5.f, -1.f + (3.f + 0.5f) * 2.f / 5.f,
                 -1.f + (2.f + 0.5f) * 2.f / 5.f};
    const MediumPoint at = m.at(c);
    CHECK(at.sigma_a.r == Approx(1.5f * m.rgb_sigma_a->sample(1, 3, 2).r));
    CHECK(at.sigma_s.b == Approx(1.5f * m.rgb_sigma_s->sample(1, 3, 2).b));
    CHECK(m.emission_at(c).is_black());  // no Le grid: no glow
    CHECK(m.at({1.2f, 0.f, 0.f}).sigma_a.is_black());
    const kern::GridFrame& f = m.density->majorant_frame();
    int violations = 0;
    for (uint64_t i = 0; i < 100000; ++i) {
        const Vec3 p{rng::uniform(8, 1, i, 0) * 2.f - 1.f, rng::uniform(8, 1, i, 1) * 2.f - 1.f,
                     rng::uniform(8, 1, i, 2) * 2.f - 1.f};
        const MediumPoint q = m.at(p);
        int cell[3];
        const float pp[3] = {p.x, p.y, p.z};
        for (int a = 0; a < 3; ++a)
            cell[a] = std::clamp(int((pp[a] - f.lo[a]) * f.inv_cell[a]), 0, f.res[a] - 1);
        const float maj = m.majorant() * m.density->majorant(f.index(cell[0], cell[1], cell[2]));
        if ((q.sigma_a + q.sigma_s).max_component() > maj * 1.00001f) ++violations;
    }
    CHECK(violations == 0);
}

TEST_CASE("rgbgrid: ratio and delta tracking equal exp(-optical depth) in every channel",
          "[media][fast]") {
    const Medium m = rgb_medium(9, 1.2f);
    const Vec3 rays[3][2] = {{{-1.5f, 0.1f, 0.2f}, {1, 0, 0}},
                             {{0.3f, -1.4f, -0.6f}, {0.1f, 0.9f, 0.4f}},
                             {{0.9f, 0.9f, 0.9f}, {-0.6f, -0.5f, -0.62f}}};
    for (int r = 0; r < 3; ++r) {
        const Vec3 o = rays[r][0], d = normalize(rays[r][1]);
        const float t_end = 3.f;
        const RGB exact = test::exact_transmittance(m, o, d, t_end);
        const int n = 100000;
        RGB ratio{0.f}, pass{0.f};
        for (int i = 0; i < n; ++i) {
            test::Draws u{91, uint64_t(r), uint64_t(i)};
            ratio += ratio_track_grid(m, o, d, t_end, u);
            test::Draws v{91, uint64_t(10 + r), uint64_t(i)};
            const FreeFlight f = delta_track_grid(m, o, d, t_end, RGB{1.f}, v);
            if (f.event == FreeFlight::Event::Pass) pass += f.weight;
        }
        INFO("ray " << r << ": exact " << exact.r << " " << exact.g << " " << exact.b);
        CHECK(ratio.r / n == Approx(exact.r).margin(0.01));
        CHECK(ratio.g / n == Approx(exact.g).margin(0.01));
        CHECK(ratio.b / n == Approx(exact.b).margin(0.01));
        CHECK(pass.r / n == Approx(exact.r).margin(0.01));
        CHECK(pass.g / n == Approx(exact.g).margin(0.01));
        CHECK(pass.b / n == Approx(exact.b).margin(0.01));
    }
}

TEST_CASE("emitting grid media: a camera deep inside sees Le (grid and rgbgrid, XML)",
          "[media][render]") {
    test::TempDir dir;
    // 2^3 samples, all equal: the medium is uniform away from the box's faces, 100 units off.
    auto write = [&](const char* name, std::vector<float> v) {
        std::ofstream f(dir.file(name), std::ios::binary);
        f.write(reinterpret_cast<const char*>(v.data()), std::streamsize(4 * v.size()));
    };
    write("ones.raw", std::vector<float>(8, 1.f));
    std::vector<float> sa, ss, le;
    for (int i = 0; i < 8; ++i) {
        sa.insert(sa.end(), {0.5f, 0.5f, 0.5f});
        ss.insert(ss.end(), {0.5f, 0.2f, 0.f});
        le.insert(le.end(), {1.f, 0.5f, 0.25f});
    }
    write("sa.raw", sa);
    write("ss.raw", ss);
    write("le.raw", le);
    const std::string box =
        "<p0 x=\"-200\" y=\"-200\" z=\"-200\"/><p1 x=\"200\" y=\"200\" z=\"200\"/>";
    const std::string media[2] = {
        "<medium name=\"glow\" type=\"grid\" nx=\"2\" ny=\"2\" nz=\"2\" src=\"ones.raw\">"
        "<sigma_a r=\"0.5\" g=\"0.5\" b=\"0.5\"/><sigma_s r=\"0.5\" g=\"0.2\" b=\"0\"/>"
        "<emission r=\"1\" g=\"0.5\" b=\"0.25\"/>" +
            box + "</medium>",
        "<medium name=\"glow\" type=\"rgbgrid\" nx=\"2\" ny=\"2\" nz=\"2\" sigma_a_src=\"sa.raw\" "
        "sigma_s_src=\"ss.raw\" emission_src=\"le.raw\">" +
            box + "</medium>"};
    for (const std::string& medium : media) {
        const std::string xml =
            "<scene><film width=\"16\" height=\"16\"/>\n<media>" + medium +
            "</media>\n<objects><sphere radius=\"0.01\"><center x=\"0\" y=\"0\" z=\"-1000\"/>"
            "<material type=\"lambert\"/></sphere></objects>\n"
            "<renderer type=\"volpath\" max_depth=\"200\"/>\n"
            "<camera medium=\"glow\" fov=\"60\"><eye x=\"0\" y=\"0\" z=\"0\"/>"
            "<target x=\"0\" y=\"0\" z=\"-1\"/></camera></scene>";
        TestScene s(parse_scene(xml, "glow.xml", dir.path().string()));
        REQUIRE(s.media[0].emits());
        const RGB mean = test::image_mean(render_test(s, 64 * test::effort(), 2, 5).film);
        INFO(medium.substr(0, 40) << ": " << mean.r << " " << mean.g << " " << mean.b);
        CHECK(mean.r == Approx(1.f).epsilon(0.03));
        CHECK(mean.g == Approx(0.5f).epsilon(0.03));
        CHECK(mean.b == Approx(0.25f).epsilon(0.03));
    }
}

TEST_CASE("rgbgrid and emitting uniformgrid in pbrt-v4's format, and their errors",
          "[media][fast]") {
    auto scene = [](const std::string& medium) {
        return "LookAt 0 0 5 0 0 0 0 1 0\nCamera \"perspective\"\nWorldBegin\nAttributeBegin\n"
               "  Translate 1 0 0\n" +
               medium + "\nAttributeEnd\nMediumInterface \"m\" \"\"\nMaterial \"interface\"\n" +
               "Shape \"sphere\" \"float radius\" 3\n";
    };
    const Scene p = parse_pbrt_scene(
        scene("MakeNamedMedium \"m\" \"string type\" \"rgbgrid\" \"integer nx\" 2 \"rgb sigma_a\" "
              "[0.1 0.2 0.3  0.4 0.5 0.6] \"rgb Le\" [1 1 1  2 2 2] \"float scale\" 2 "
              "\"float Lescale\" 0.5"),
        "t.pbrt", ".");
    REQUIRE(p.media.size() == 1);
    const Medium& m = p.media[0];
    CHECK(m.kind == MediumKind::RGBGrid);
    CHECK(m.rgb_sigma_s == nullptr);  // pbrt-v4's default: 1 throughout the box
    CHECK(m.grid_scale == 2.f);
    // pbrt-v4 does not normalise an rgbgrid's Le by the illuminant's luminance.
    CHECK(m.le_factor == Approx(0.5f * 106.856895f));
    CHECK(m.density->box().lo.x == Approx(1.f));
    // At the second sample's centre: sigma_a (0.4, 0.5, 0.6) x 2, sigma_s 1 x 2.
    const MediumPoint c = m.at({1.75f, 0.5f, 0.5f});
    CHECK(c.sigma_a.g == Approx(1.f));
    CHECK(c.sigma_s.r == Approx(2.f));
    CHECK(m.density->sample(1, 0, 0) == Approx(1.6f));  // the bound: 0.6 + 1, before the scale
    // A uniformgrid's Le without "Lescale": one sample of 1 in the box's centre (pbrt-v4's).
    const Scene u = parse_pbrt_scene(
        scene("MakeNamedMedium \"m\" \"string type\" \"uniformgrid\" \"integer nx\" 1 \"float "
              "density\" [1] \"rgb Le\" [1 0.5 0.25]"),
        "t.pbrt", ".");
    REQUIRE(u.media[0].le_scale);
    CHECK(u.media[0].emission_at({1.5f, 0.5f, 0.5f}).g == Approx(0.5f));
    // A quarter of the way from the face: three quarters of the centre's value.
    CHECK(u.media[0].emission_at({1.25f, 0.5f, 0.5f}).g == Approx(0.375f));
    auto says = [](const std::string& message, const std::string& part) {
        const bool found = message.find(part) != std::string::npos;
        if (!found) UNSCOPED_INFO("the message: " << message);
        return found;
    };
    CHECK(says(error_of([&] {
                   parse_pbrt_scene(scene("MakeNamedMedium \"m\" \"string type\" \"rgbgrid\" "
                                          "\"integer nx\" 2 \"rgb sigma_a\" [1 1 1]"),
                                    "t.pbrt", ".");
               }),
               "t.pbrt:6: MakeNamedMedium \"m\": \"sigma_a\" has 1 values, nx * ny * nz is 2"));
    CHECK(says(error_of([&] {
                   parse_pbrt_scene(scene("MakeNamedMedium \"m\" \"string type\" \"rgbgrid\" "
                                          "\"rgb sigma_s\" [1 1 1] \"rgb Le\" [1 1 1]"),
                                    "t.pbrt", ".");
               }),
               "an rgbgrid's \"Le\" needs \"sigma_a\""));
    // A uniformgrid's temperature glows as a blackbody, scaled by pbrt-v4's single centre sample.
    const Scene hot = parse_pbrt_scene(
        scene("MakeNamedMedium \"m\" \"string type\" \"uniformgrid\" \"float density\" [1] "
              "\"float temperature\" [2100] \"float temperatureoffset\" 100"),
        "t.pbrt", ".");
    REQUIRE(hot.media[0].temperature);
    CHECK(hot.media[0].emits());
    CHECK(hot.media[0].emission_at({1.5f, 0.5f, 0.5f}).r ==
          Approx(pbrt::blackbody_emission_rgb(2000.f).r).epsilon(0.002));
    // A quarter of the way from the face both the temperature (to 3/4 of 2100 K) and the
    // emission's scale (to 3/4) fade, as pbrt-v4's single samples do.
    CHECK(hot.media[0].emission_at({1.25f, 0.5f, 0.5f}).r ==
          Approx(0.75f * pbrt::blackbody_emission_rgb(0.75f * 2100.f - 100.f).r).epsilon(0.002));
    CHECK(says(error_of([&] {
                   parse_pbrt_scene(scene("MakeNamedMedium \"m\" \"string type\" \"uniformgrid\" "
                                          "\"float density\" [1] \"float temperature\" [900] "
                                          "\"rgb Le\" [1 1 1]"),
                                    "t.pbrt", ".");
               }),
               "give \"Le\" or \"temperature\", not both"));
    CHECK(says(error_of([&] {
                   parse_pbrt_scene(scene("MakeNamedMedium \"m\" \"string type\" \"uniformgrid\" "
                                          "\"float density\" [1] \"rgb Le\" [1 1 1] \"float "
                                          "Lescale\" [1 2]"),
                                    "t.pbrt", ".");
               }),
               "\"Lescale\" has 2 values, nx * ny * nz is 1"));
    // The XML form's errors.
    test::TempDir dir;
    {
        std::ofstream f(dir.file("six.raw"), std::ios::binary);
        const float v[6] = {1, 1, 1, 1, 1, 1};
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
    auto xml_error = [&](const std::string& medium) {
        return error_of([&] { parse_scene(xml(medium), "g.xml", dir.path().string()); });
    };
    CHECK(xml_error("<medium name=\"m\" type=\"rgbgrid\" nx=\"2\" ny=\"1\" nz=\"1\" "
                    "sigma_s_src=\"six.raw\">" +
                    box + "</medium>")
              .empty());
    CHECK(says(xml_error("<medium name=\"m\" type=\"rgbgrid\" nx=\"2\" ny=\"2\" nz=\"1\" "
                         "sigma_s_src=\"six.raw\">" +
                         box + "</medium>"),
               "g.xml:2: sample file 'six.raw' has 24 bytes; 12 float32 values are 48"));
    CHECK(says(xml_error("<medium name=\"m\" type=\"rgbgrid\" nx=\"2\" ny=\"1\" nz=\"1\" "
                         "sigma_s_src=\"six.raw\" emission_src=\"six.raw\">" +
                         box + "</medium>"),
               "an emitting medium needs absorption"));
    CHECK(says(xml_error("<medium name=\"m\" type=\"rgbgrid\" nx=\"2\" ny=\"1\" nz=\"1\" "
                         "sigma_s_src=\"six.raw\"><sigma_a r=\"1\" g=\"1\" b=\"1\"/>" +
                         box + "</medium>"),
               "<sigma_a> belongs to media other than rgbgrid"));
    CHECK(says(xml_error("<medium name=\"m\" emission_src=\"six.raw\"><sigma_a r=\"1\" g=\"1\" "
                         "b=\"1\"/></medium>"),
               "'emission_src' belongs to an rgbgrid medium"));
}
