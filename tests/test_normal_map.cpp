// Tangent-space normal maps (Material::normal_map, applied by surface_at): a flat map changes
// nothing, a tilted one turns the shading normal about the surface's u direction by its
// angle, and a Lambertian floor under a distant light takes the radiance the turned normal's
// cosine predicts, through the pbrt-v4 importer's `normalmap` and the XML's <normal_map>.
#include <catch2/catch.hpp>
#include <cmath>

#include "engine/core/error.h"
#include "engine/film/image_io.h"
#include "engine/scene/pbrt_loader.h"
#include "engine/scene/xml_loader.h"
#include "engine/transport/common/surface.h"
#include "lit_floor_scene.h"
#include "test_util.h"

using namespace foton;

namespace {

// A 4 x 4 normal map of one tangent-space normal n, encoded (n + 1) / 2.
std::string write_map(const test::TempDir& dir, const std::string& name, const Vec3& n) {
    Film f(4, 4);
    for (RGB& p : f.pixels) p = RGB{0.5f * (n.x + 1.f), 0.5f * (n.y + 1.f), 0.5f * (n.z + 1.f)};
    const std::string path = dir.file(name);
    write_exr(path, f);
    return path;
}

// The shared lit floor (lit_floor_scene.h), its Lambert carrying normal map `map`.
std::string floor_scene(const std::string& map, const Vec3& l) {
    return test::lit_floor_scene(
        "", map.empty() ? std::string() : "\"string normalmap\" \"" + map + "\"", l);
}

}  // namespace

TEST_CASE("normal maps: the shading normal turns by the map's tangent-space normal",
          "[normal_map][fast]") {
    test::TempDir dir;
    const float a = 30.f * kPi / 180.f;
    const std::string flat = write_map(dir, "flat.exr", {0.f, 0.f, 1.f});
    const std::string tilt = write_map(dir, "tilt.exr", {std::sin(a), 0.f, std::cos(a)});
    const std::string side = write_map(dir, "side.exr", {0.f, std::sin(a), std::cos(a)});
    auto normal_at = [&](const std::string& map) {
        const Scene s = parse_pbrt_scene(floor_scene(map, {0, 0, 1}), "floor.pbrt", ".");
        // A ray straight down onto the floor's first triangle.
        const Vec3 o{10.f, -20.f, 5.f}, d{0.f, 0.f, -1.f};
        return surface_at(s, 0, 0, 5.f, 0.3f, 0.2f, o, d).ns;
    };
    const Vec3 n0 = normal_at(flat);
    CHECK(n0.z == Approx(1.f));
    // Along u (+x): the normal leans towards +x by 30 degrees, B = N x T = +y.
    const Vec3 n1 = normal_at(tilt);
    CHECK(n1.x == Approx(std::sin(a)).margin(2e-3));
    CHECK(n1.y == Approx(0.f).margin(2e-3));
    CHECK(n1.z == Approx(std::cos(a)).margin(2e-3));
    const Vec3 n2 = normal_at(side);
    CHECK(n2.y == Approx(std::sin(a)).margin(2e-3));
    CHECK(n2.x == Approx(0.f).margin(2e-3));
}

TEST_CASE("normal maps: a Lambertian floor under a distant light follows the mapped normal",
          "[normal_map]") {
    test::TempDir dir;
    const float a = 30.f * kPi / 180.f;
    const Vec3 l = normalize(Vec3{0.6f, 0.f, 0.8f});  // towards the light
    struct Case {
        Vec3 map;
        double cosine;  // of the mapped normal with l
    };
    const Case cases[] = {
        {{0.f, 0.f, 1.f}, 0.8},
        {{std::sin(a), 0.f, std::cos(a)}, 0.6 * std::sin(a) + 0.8 * std::cos(a)},
        {{-std::sin(a), 0.f, std::cos(a)}, -0.6 * std::sin(a) + 0.8 * std::cos(a)}};
    int k = 0;
    for (const Case& c : cases) {
        std::string name = std::to_string(k++);  // (GCC 12 misreads "m" + to_string: -Wrestrict)
        name += ".exr";
        const std::string map = write_map(dir, name, c.map);
        TestScene s(parse_pbrt_scene(floor_scene(map, l), "floor.pbrt", "."));
        const Film img = render_test(s, 4).film;
        RGB sum{0.f};
        for (const RGB& p : img.pixels) sum += p;
        const double mean = sum.g / double(img.pixels.size());
        INFO("map normal " << c.map.x << " " << c.map.y << " " << c.map.z);
        // L = rho / pi * E * cos(n_s, l).
        CHECK(mean == Approx(0.5 / kPi * c.cosine).epsilon(1e-3));
    }
}

TEST_CASE("normal maps: the XML reads <normal_map>, mixes take one, bad files fail at their line",
          "[normal_map][xml][fast]") {
    test::TempDir dir;
    write_map(dir, "bumps.exr", {0.2f, 0.1f, 0.97f});
    auto scene = [&](const std::string& material) {
        return parse_scene(
            "<scene><objects><sphere radius=\"1\"><center x=\"0\" y=\"0\" z=\"0\"/>" + material +
                "</sphere></objects><film width=\"4\" height=\"4\"/><camera><eye x=\"0\" "
                "y=\"0\" z=\"-5\"/><target x=\"0\" y=\"0\" z=\"0\"/></camera></scene>",
            "nm.xml", dir.path().string());
    };
    const Scene s = scene(R"(<material type="lambert"><normal_map src="bumps.exr"/></material>)");
    const Material& m = s.materials.back();
    REQUIRE(m.normal_map >= 0);
    // Read linearly: the texel is the file's value, not sRGB-decoded.
    const RGB texel = s.textures[std::size_t(m.normal_map)].eval(s.texture_images, {0.5f, 0.5f});
    CHECK(texel.r == Approx(0.6f).margin(1e-3));
    const Scene mixed = scene(R"(<material type="mix"><material type="lambert" weight="0.5">
        <normal_map src="bumps.exr"/></material><material type="conductor" weight="0.5"/>
        </material>)");
    CHECK(mixed.materials.back().normal_map >= 0);
    CHECK_THROWS_WITH(scene(R"(<material type="lambert"><normal_map src="none.exr"/></material>)"),
                      Catch::Contains("nm.xml:1") && Catch::Contains("none.exr"));
    CHECK_THROWS_AS(
        parse_pbrt_scene(floor_scene(dir.file("missing.exr"), {0, 0, 1}), "f.pbrt", "."),
        InputError);
}
